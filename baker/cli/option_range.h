#pragma once
/// A numeric option's range, checked with one wording whatever CLI11's
/// version: CLI11 2.3 (Debian 12) says "Value 0 not in range 1 to 65536",
/// 2.4 and later (Debian 13) "Value 0 not in range [1 - 65536]". The
/// program says "must be in [MIN, MAX], got VALUE", as its file readers do.

#include <iomanip>
#include <sstream>
#include <string>
#include <type_traits>

#include <CLI/CLI.hpp>

namespace clothbake::cli {

/// Spells a bound as a person writes it: 1048576, not 1.04858e+06; 0.5.
template <typename T>
std::string spell_bound(T value) {
  std::ostringstream out;
  out << std::setprecision(15) << value;
  return out.str();
}

/// Accepts a number in [min, max]; refuses anything else, naming the range.
template <typename T>
CLI::Validator in_range(T min, T max) {
  const std::string bounds = "[" + spell_bound(min) + ", " + spell_bound(max) + "]";
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        T value{};
        if (!CLI::detail::lexical_cast(text, value) || !(value >= min && value <= max)) {
          return "must be in " + bounds + ", got " + text;
        }
        return {};
      },
      std::string(std::is_integral_v<T> ? "INT" : "FLOAT") + " in " + bounds);
}

}  // namespace clothbake::cli
