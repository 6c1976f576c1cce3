#pragma once
// FNV-1a, 64 bits: the checksum of checkpoint files, the problem fingerprint and the
// identity of an active set (solvers/active_set_history.hpp). Not cryptographic.
#include <cstddef>
#include <cstdint>

namespace vpc {

inline constexpr std::uint64_t kFnv1aOffset = 1469598103934665603ull;

/// The hash of n bytes, continuing from h.
inline std::uint64_t fnv1a(const void* data, std::size_t n, std::uint64_t h = kFnv1aOffset) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

}  // namespace vpc
