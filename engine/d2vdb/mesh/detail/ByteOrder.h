// Reading and writing binary scalars in an explicit byte order, independent of the host's.
// Internal to the mesh file formats (binary PLY and STL).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>

namespace d2vdb::detail {

/// Byte order of a binary file's scalars.
enum class ByteOrder { Little, Big };

/// The unsigned integer type with the size of T (T is 1, 2, 4 or 8 bytes).
template <typename T>
using UnsignedOfSize = std::conditional_t<
    sizeof(T) == 1, std::uint8_t,
    std::conditional_t<sizeof(T) == 2, std::uint16_t,
                       std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;

/// Decodes the arithmetic value T stored in `sizeof(T)` bytes at `bytes` in the given order.
/// The caller guarantees that the bytes exist; floats are taken bit for bit (IEEE 754).
template <typename T>
T loadScalar(const char* bytes, ByteOrder order) {
  static_assert(std::is_arithmetic_v<T>, "loadScalar decodes arithmetic types only");
  using Bits = UnsignedOfSize<T>;
  Bits bits = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    const std::size_t shift = order == ByteOrder::Little ? 8 * i : 8 * (sizeof(T) - 1 - i);
    bits = static_cast<Bits>(bits |
                             (static_cast<Bits>(static_cast<unsigned char>(bytes[i])) << shift));
  }
  T value;
  std::memcpy(&value, &bits, sizeof(T));
  return value;
}

/// Appends the `sizeof(T)` bytes of `value` to `out` in the given order (inverse of loadScalar).
template <typename T>
void appendScalar(std::string& out, T value, ByteOrder order) {
  static_assert(std::is_arithmetic_v<T>, "appendScalar encodes arithmetic types only");
  using Bits = UnsignedOfSize<T>;
  Bits bits;
  std::memcpy(&bits, &value, sizeof(T));
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    const std::size_t shift = order == ByteOrder::Little ? 8 * i : 8 * (sizeof(T) - 1 - i);
    out.push_back(static_cast<char>(static_cast<unsigned char>((bits >> shift) & 0xFFu)));
  }
}

}  // namespace d2vdb::detail
