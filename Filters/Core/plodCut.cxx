// SPDX-License-Identifier: BSD-3-Clause
#include "plodCut.h"

#include <algorithm>
#include <vector>

namespace plod
{

void UniformCut(const OctreeView& v, int level, uint8_t* state)
{
  const bool open = level < 0 || level > v.FinestLevel;
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    if (open)
    {
      state[n] = v.IsLeaf(n) ? CutOpen : NotInCut;
    }
    else
    {
      state[n] = v.Level[n] == level ? CutDrawn : NotInCut;
    }
  }
}

void PredicateCut(const OctreeView& v, const std::function<bool(int64_t)>& refine, uint8_t* state)
{
  std::fill(state, state + v.NumberOfNodes, NotInCut);
  if (v.NumberOfNodes == 0)
  {
    return;
  }
  std::vector<int32_t> stack{ 0 };
  while (!stack.empty())
  {
    const int32_t n = stack.back();
    stack.pop_back();
    const bool more = refine(n);
    if (v.IsLeaf(n))
    {
      state[n] = more ? CutOpen : CutDrawn;
      continue;
    }
    if (!more)
    {
      state[n] = CutDrawn;
      continue;
    }
    const int count = __builtin_popcount(v.ChildMask[n]);
    for (int c = 0; c < count; ++c)
    {
      stack.push_back(v.FirstChild[n] + c);
    }
  }
}

bool ValidateCut(const OctreeView& v, const uint8_t* state, std::string* why)
{
  auto fail = [why](const std::string& text) {
    if (why)
    {
      *why = text;
    }
    return false;
  };
  // nodes are stored parents first: one pass counts the cut nodes on each path
  std::vector<uint8_t> above(static_cast<size_t>(v.NumberOfNodes), 0);
  for (int64_t n = 0; n < v.NumberOfNodes; ++n)
  {
    const uint8_t s = state[n];
    if (s > CutOpen)
    {
      return fail("node " + std::to_string(n) + " has cut state " + std::to_string(int(s)) +
        " (valid states are 0 to 3)");
    }
    if (s == CutOpen && !v.IsLeaf(n))
    {
      return fail("node " + std::to_string(n) + " is opened but is not a leaf");
    }
    const int parentCount = n > 0 ? above[v.Parent[n]] : 0;
    const int count = parentCount + (s != NotInCut ? 1 : 0);
    if (count > 1)
    {
      return fail("node " + std::to_string(n) + " is in the cut below another cut node");
    }
    above[n] = static_cast<uint8_t>(count);
    if (v.IsLeaf(n) && count == 0)
    {
      return fail("leaf " + std::to_string(n) + " has no ancestor in the cut");
    }
  }
  return true;
}

} // namespace plod
