#pragma once
// Decoding an LCM message from bytes others wrote (a record after a crash, a fuzzer): lcm-gen's
// decoders trust a string's length prefix: 0 asks std::string for SIZE_MAX bytes
// (std::length_error), INT32_MIN overflows `len - 1`. The strings of our types lead the message
// (after the 8-byte fingerprint), so they are checked here, before the generated code sees them;
// whatever the generated code still throws is a failed decode, not an exception.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <span>

namespace ambdrop {

/// Leading string fields of the record types that have them (io/lcm/lcm_types/).
inline constexpr int kRecordHeaderStrings = 5;  ///< record_header_t
inline constexpr int kRecordFooterStrings = 1;  ///< record_footer_t

/// Whether the first `strings` string fields after the fingerprint each have a length in
/// [1, what is left] and end in their NUL.
inline bool LcmLeadingStringsSound(std::span<const std::uint8_t> data, int strings) noexcept {
  std::size_t pos = 8;
  for (int i = 0; i < strings; ++i) {
    if (data.size() < pos + 4) return false;
    const std::int64_t length = static_cast<std::int32_t>(
        (std::uint32_t{data[pos]} << 24) | (std::uint32_t{data[pos + 1]} << 16) |
        (std::uint32_t{data[pos + 2]} << 8) | std::uint32_t{data[pos + 3]});
    pos += 4;
    // The length counts the terminating NUL, which must be there.
    if (length < 1 || static_cast<std::uint64_t>(length) > data.size() - pos) return false;
    pos += static_cast<std::size_t>(length);
    if (data[pos - 1] != 0) return false;
  }
  return true;
}

/// Decodes the whole of `data` as Message: false for a short, long, foreign or unsound one.
template <typename Message>
bool DecodeLcmGuarded(std::span<const std::uint8_t> data, Message* out,
                      int leading_strings = 0) noexcept {
  if (data.size() > 0x7fffffff || !LcmLeadingStringsSound(data, leading_strings)) return false;
  try {
    const int n = out->decode(data.data(), 0, static_cast<int>(data.size()));
    return n == static_cast<int>(data.size());
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace ambdrop
