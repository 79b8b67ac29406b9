// The one exception type of wedge. Kernel functions throw wedge::Error on bad input with a
// message a person can act on: what was wrong, which argument, which value. The Lua layer
// turns it into a Lua error at the script's file and line. Nothing in wedge aborts on bad input.
#pragma once
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace wedge {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

namespace detail {
// One piece of a message; a NaN prints as "nan" (its sign bit means nothing to a reader).
template <class T>
void put(std::ostream& out, const T& x) {
  if constexpr (std::is_floating_point_v<T>) {
    if (std::isnan(x)) {
      out << "nan";
      return;
    }
  }
  out << x;
}
}  // namespace detail

// Builds a message from pieces and throws it: fail("radius must be positive, got ", r).
template <class... Parts>
[[noreturn]] void fail(const Parts&... parts) {
  std::ostringstream out;
  out.precision(17);
  (detail::put(out, parts), ...);
  throw Error(out.str());
}

// Throws unless x is a finite number; `what` names the argument ("radius").
void require_finite(double x, const char* what);
// Throws unless x > 0 and finite.
void require_positive(double x, const char* what);

}  // namespace wedge
