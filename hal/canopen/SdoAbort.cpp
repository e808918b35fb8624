#include "hal/canopen/SdoAbort.hpp"

namespace carril::hal {

namespace {

struct AbortEntry {
  std::uint32_t code;
  const char* meaning;
};

// CiA 301 (v4.2) table 22, "SDO abort codes". Short lower-case phrases: they end up inside a
// one-line message that already names the node and the object.
constexpr AbortEntry kAbortTable[] = {
    {0x05030000U, "toggle bit not alternated"},
    {0x05040000U, "SDO protocol timed out"},
    {0x05040001U, "command specifier not valid or unknown"},
    {0x05040002U, "invalid block size"},
    {0x05040003U, "invalid sequence number"},
    {0x05040004U, "CRC error"},
    {0x05040005U, "out of memory"},
    {0x06010000U, "unsupported access to an object"},
    {0x06010001U, "attempt to read a write-only object"},
    {0x06010002U, "attempt to write a read-only object"},
    {0x06020000U, "object does not exist in the object dictionary"},
    {0x06040041U, "object cannot be mapped to the PDO"},
    {0x06040042U, "mapped objects would exceed the PDO length"},
    {0x06040043U, "general parameter incompatibility"},
    {0x06040047U, "general internal incompatibility in the device"},
    {0x06060000U, "access failed due to a hardware error"},
    {0x06070010U, "data type does not match, length of service parameter does not match"},
    {0x06070012U, "data type does not match, length of service parameter too high"},
    {0x06070013U, "data type does not match, length of service parameter too low"},
    {0x06090011U, "sub-index does not exist"},
    {0x06090030U, "value range exceeded"},
    {0x06090031U, "value written too high"},
    {0x06090032U, "value written too low"},
    {0x06090036U, "maximum value is less than minimum value"},
    {0x060A0023U, "resource not available: SDO connection"},
    {0x08000000U, "general error"},
    {0x08000020U, "data cannot be transferred or stored to the application"},
    {0x08000021U, "data cannot be transferred or stored because of local control"},
    {0x08000022U, "data cannot be transferred or stored because of the present device state"},
    {0x08000023U, "object dictionary dynamic generation failed or no object dictionary"},
    {0x08000024U, "no data available"},
};

}  // namespace

const char* sdo_abort_meaning(std::uint32_t code) {
  // 31 entries: a linear scan is cheaper than anything cleverer and is only run on failure.
  for (const AbortEntry& e : kAbortTable) {
    if (e.code == code) return e.meaning;
  }
  return "unknown abort code";
}

}  // namespace carril::hal
