// Progress of long tessellations, for a progress bar (the runner's): `progress(done, expected,
// false)` is called as tessellate() makes points, with the number of points its size estimate
// expects (a guide: the count may pass it), and `progress(done, expected, true)` once when the
// tessellation ends or fails. Only a tessellation whose estimate is large (10,000 points or
// more) reports. Installed for the calling thread only (tessellations on other threads, such as a CSG
// tree's parallel operands, do not report); nullptr removes it; the caller keeps the function alive.
#pragma once
#include <cstddef>
#include <functional>

namespace wedge {

using TessellateProgress = std::function<void(std::size_t done, std::size_t expected, bool finished)>;
void set_tessellate_progress(const TessellateProgress* progress);

// A poll for a cancel request: tessellate() calls it on the thread that runs it between faces and
// every 1024 points or triangles it looks at (milliseconds apart even at a very fine tolerance),
// and it stops the tessellation by throwing (the CSG evaluator's poll throws wedge::Cancelled, so
// a cancel raised while a leaf is tessellated is seen at once, not when the leaf is done). For the
// calling thread only; returns the poll it replaces, to be put back; nullptr removes it.
using TessellatePoll = std::function<void()>;
const TessellatePoll* set_tessellate_poll(const TessellatePoll* poll);
// The calling thread's poll, or nullptr. The mesh writers (write_mesh) call it between blocks of
// 64 KiB, so a cancel stops an export at once, its old file left as it was.
const TessellatePoll* tessellate_poll();

}  // namespace wedge
