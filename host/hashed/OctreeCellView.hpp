#pragma once
// Hashed shading's "octree-cell" debug view (`render --octree-cell-view F`,
// the viewer's view list): each pixel coloured by the octree node that holds
// its surface point, as the shader's lookup finds it (LinklessOctree::cellAt):
//   a leaf listing lights: a colour mixed from its depth and coordinates
//     (idColour: neighbouring cells, and a cell and its parent, differ);
//   a node listing none: a dark grey, also mixed from its key, so empty cells
//     still show their extent;
//   outside the octree's cube: dark blue; sky: black.
// The four kinds never share a colour in an 8-bit image (greys stay below
// idColour's channel levels, the blue's red and green too).
// The surface points come from the frame's depth (DebugViewInputs::worldAt),
// the same reconstruction as the exact lower bound's.
#include <vector>

#include "host/assign/DebugViewInputs.hpp"
#include "host/hashed/LinklessOctree.hpp"
#include "host/util/Heatmap.hpp"

namespace ml::hashed {

Rgb octreeCellColour(const LinklessOctree::Cell& cell);
// RGBA floats, frame.width x frame.height, row 0 at the bottom.
std::vector<float> octreeCellViewRgba(const LinklessOctree& octree, const DebugViewInputs& frame);

}  // namespace ml::hashed
