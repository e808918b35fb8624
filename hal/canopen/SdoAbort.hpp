#pragma once
// CiA 301 SDO abort codes (the 32-bit code an abort transfer carries in bytes 4..7) and their
// meaning, so a failed transfer can say why in words and not only in hex.
#include <cstdint>

namespace carril::hal {

constexpr std::uint32_t kSdoAbortToggle = 0x05030000U;      // toggle bit not alternated
constexpr std::uint32_t kSdoAbortTimeout = 0x05040000U;     // SDO protocol timed out
constexpr std::uint32_t kSdoAbortBadCommand = 0x05040001U;  // command specifier not valid
constexpr std::uint32_t kSdoAbortNoObject = 0x06020000U;    // object does not exist
constexpr std::uint32_t kSdoAbortNoSubindex = 0x06090011U;  // sub-index does not exist
constexpr std::uint32_t kSdoAbortValueRange = 0x06090030U;  // value range exceeded
constexpr std::uint32_t kSdoAbortGeneral = 0x08000000U;     // general error

// The CiA 301 meaning of an abort code, lower case, static storage; "unknown abort code" for a
// code outside the table (manufacturer-specific codes included).
const char* sdo_abort_meaning(std::uint32_t code);

}  // namespace carril::hal
