#pragma once
/// A 64-bit hash as the files and messages spell it: 16 lower-case hex
/// digits (a volume texture's content hash, a scene's fingerprint).

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>

namespace clothbake {

inline std::string hex16(uint64_t h) {
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

/// The value of exactly 16 hex digits, or nothing.
inline std::optional<uint64_t> parse_hex16(const std::string& s) {
  if (s.size() != 16) return std::nullopt;
  uint64_t v = 0;
  for (char c : s) {
    int d = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10
                                             : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
    if (d < 0) return std::nullopt;
    v = v << 4 | uint64_t(d);
  }
  return v;
}

}  // namespace clothbake
