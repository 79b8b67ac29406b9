#include "kernel/error.h"

#include <cmath>

namespace wedge {

void require_finite(double x, const char* what) {
  if (!std::isfinite(x)) fail(what, " must be a finite number, got ", x);
}

void require_positive(double x, const char* what) {
  require_finite(x, what);
  if (!(x > 0)) fail(what, " must be positive, got ", x);
}

}  // namespace wedge
