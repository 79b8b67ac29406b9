// wedge::brep — the winged-edge boundary representation. The typed ids of its elements: each is
// an index into one arena of the model (see kernel/ids.h).
#pragma once
#include "kernel/kernel.h"
#include "surfaces/surfaces.h"

namespace wedge {

using VertexId = Id<struct VertexTag>;
using EdgeId = Id<struct EdgeTag>;
using LoopId = Id<struct LoopTag>;
using FaceId = Id<struct FaceTag>;
using ShellId = Id<struct ShellTag>;

// The element counts of a model, as the Euler–Poincaré formula uses them:
// V - E + F - R + 2H - 2S = 0, with R the inner loops (rings) and H the through-holes (genus).
struct EulerCounts {
  long V = 0, E = 0, F = 0, R = 0, H = 0, S = 0;
  long characteristic() const { return V - E + F - R + 2 * H - 2 * S; }
  bool operator==(const EulerCounts&) const = default;
};

}  // namespace wedge
