// Tolerances are explicit arguments in wedge, never hidden globals.
#pragma once
#include <cstddef>

namespace wedge {

struct Tolerance {
  double chordal = 0.01;      // max distance between a curve/surface and its polyline/mesh (model units)
  double angular = 15.0;      // max turn between neighbouring segments or facets (degrees)
  double distance = 1e-9;     // two points closer than this are the same point (model units)
  // The triangle budget of one tessellation: a tolerance whose estimated mesh is larger is an
  // error giving the estimate, before the work (and the memory) is spent. Raise it to go further.
  std::size_t max_triangles = 10'000'000;
  // The work budget of one boolean (csg/boolean.h, kDefaultMaxCrossings): the most points where
  // three operands' surfaces cross; operands that nearly coincide cross everywhere, and a boolean
  // whose estimate is larger is an error giving it, before the work. Raise it to go further.
  std::size_t max_crossings = 50'000;
};

}  // namespace wedge
