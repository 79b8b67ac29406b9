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

}  // namespace wedge
