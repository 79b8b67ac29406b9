// Tolerances are explicit arguments in wedge, never hidden globals.
#pragma once

namespace wedge {

struct Tolerance {
  double chordal = 0.01;      // max distance between a curve/surface and its polyline/mesh (model units)
  double angular = 15.0;      // max turn between neighbouring segments or facets (degrees)
  double distance = 1e-9;     // two points closer than this are the same point (model units)
};

}  // namespace wedge
