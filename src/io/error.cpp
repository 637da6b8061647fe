// The shared range check (io/error.h).
#include <fmt/format.h>
#include <microshadow/io/error.h>

namespace msh {

void require_range(double v, double lo, double hi, const std::string& what) {
  if (!(v >= lo && v <= hi)) throw InputError(fmt::format("{} must be in [{}, {}], got {}", what, lo, hi, v));
}

}  // namespace msh
