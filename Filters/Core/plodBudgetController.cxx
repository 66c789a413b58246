// SPDX-License-Identifier: BSD-3-Clause
// Frame-time target (issue 14): see plodBudgetController.h for the control law.
#include "plodBudgetController.h"

#include <algorithm>
#include <cmath>

namespace plod
{

bool ValidateFrameTimeTarget(const FrameTimeTarget& t, std::string* why)
{
  auto fail = [why](const char* text) {
    if (why)
    {
      *why = text;
    }
    return false;
  };
  if (!std::isfinite(t.Target))
  {
    return fail("the target frame time is not finite");
  }
  if (!(t.Gain > 0 && t.Gain <= 1))
  {
    return fail("the gain must lie in (0, 1]");
  }
  if (!(t.MaxStep > 1 && std::isfinite(t.MaxStep)))
  {
    return fail("the largest step must be a finite factor above 1");
  }
  if (!(t.DeadBand >= 0 && t.DeadBand < 0.5))
  {
    return fail("the dead band must lie in [0, 0.5)");
  }
  if (t.MinimumBudget < 1 || t.MaximumBudget < t.MinimumBudget)
  {
    return fail("the budget limits must satisfy 1 <= minimum <= maximum");
  }
  return true;
}

void BudgetController::Reset()
{
  this->Budget = 0;
  this->Count = 0;
  this->Measured = 0;
}

int64_t BudgetController::Update(
  const FrameTimeTarget& settings, double seconds, int64_t drawn, bool binding)
{
  if (!(settings.Target > 0) || !ValidateFrameTimeTarget(settings, nullptr))
  {
    this->Reset();
    return 0;
  }
  const double lo = double(settings.MinimumBudget);
  const double hi = double(settings.MaximumBudget);
  drawn = std::max<int64_t>(drawn, 0);
  if (this->Budget <= 0)
  {
    // start from what the tolerances draw
    this->Budget = static_cast<int64_t>(std::min(hi, std::max(lo, double(drawn))));
  }
  if (!(seconds > 0) || !std::isfinite(seconds))
  {
    return this->Budget; // nothing measured: nothing changes
  }
  // 1. median of the last three frames
  this->Recent[this->Count % 3] = seconds;
  ++this->Count;
  const double a = this->Recent[0], b = this->Recent[1], c = this->Recent[2];
  if (this->Count == 1)
  {
    this->Measured = a;
  }
  else if (this->Count == 2)
  {
    this->Measured = std::min(a, b); // the lower of two, until there are three
  }
  else
  {
    this->Measured = std::max(std::min(a, b), std::min(std::max(a, b), c));
  }
  // 2. dead band
  const double ratio = settings.Target / this->Measured;
  if (std::abs(ratio - 1) <= settings.DeadBand)
  {
    return this->Budget;
  }
  // 3.-4. a damped, limited multiplicative step from what bound the frame
  const double factor =
    std::min(settings.MaxStep, std::max(1 / settings.MaxStep, std::pow(ratio, settings.Gain)));
  const double base =
    binding ? double(this->Budget) : std::min(double(this->Budget), double(drawn));
  // 5. limits
  const double next = std::min(hi, std::max(lo, std::round(base * factor)));
  this->Budget = static_cast<int64_t>(next);
  return this->Budget;
}

} // namespace plod
