// Numbers as stvd's front ends write them in messages and reports.
#pragma once

#include <string>

namespace stvd::text {

/// 1234567 -> "1,234,567".
std::string withThousands(unsigned long long n);
/// Fixed-point with `decimals` digits.
std::string fixed(double x, int decimals);

}  // namespace stvd::text
