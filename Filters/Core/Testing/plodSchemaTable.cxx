// SPDX-License-Identifier: BSD-3-Clause
// Prints the octree schema's Markdown page (docs/octree-schema.md):
//   plodSchemaTable > docs/octree-schema.md
#include "plodOctreeSchema.h"

#include <iostream>

int main()
{
  std::cout << plod::OctreeSchemaMarkdown();
  return 0;
}
