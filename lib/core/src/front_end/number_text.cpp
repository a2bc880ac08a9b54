#include "stvd/front_end/number_text.hpp"

#include <sstream>

namespace stvd::text {

std::string withThousands(unsigned long long n) {
  std::string digits = std::to_string(n);
  std::string out;
  const int first = static_cast<int>(digits.size() % 3);
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i != 0 && (static_cast<int>(i) - first) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string fixed(double x, int decimals) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(decimals);
  s << x;
  return s.str();
}

}  // namespace stvd::text
