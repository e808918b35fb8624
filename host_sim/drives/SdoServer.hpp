#pragma once
// A CiA 301 SDO server, expedited transfers only (every object of the emulated drive is 1, 2 or
// 4 bytes): answers upload and download requests from an ObjectDictionary with the CiA 301 abort
// codes, asks the drive whether a written value is acceptable, and can be told to abort accesses
// to chosen objects (fault injection). No heap, no blocking.
#include <cstddef>
#include <cstdint>

#include "hal/CanBus.hpp"
#include "host_sim/drives/ObjectDictionary.hpp"

namespace carril::sim {

// CiA 301 abort codes the server sends (hal/canopen/SdoAbort.hpp names the others).
constexpr std::uint32_t kAbortUnsupported = 0x06010000U;     // unsupported access
constexpr std::uint32_t kAbortReadOnly = 0x06010002U;        // attempt to write a read-only
constexpr std::uint32_t kAbortNoObject = 0x06020000U;        // object does not exist
constexpr std::uint32_t kAbortCannotMap = 0x06040041U;       // object cannot be mapped
constexpr std::uint32_t kAbortMappingTooLong = 0x06040042U;  // exceeds the PDO length
constexpr std::uint32_t kAbortLength = 0x06070010U;          // length does not match
constexpr std::uint32_t kAbortNoSubindex = 0x06090011U;      // sub-index does not exist
constexpr std::uint32_t kAbortValueRange = 0x06090030U;      // value range exceeded
constexpr std::uint32_t kAbortValueTooLow = 0x06090032U;     // value written too low
constexpr std::uint32_t kAbortBadCommand = 0x05040001U;      // command specifier unknown
constexpr std::uint32_t kAbortDeviceState = 0x08000022U;     // not in the present state

class SdoServer {
 public:
  // The drive's side of a download: checks a value before it is stored, reacts after.
  class Hooks {
   public:
    virtual ~Hooks() = default;
    // 0 to accept `value` (raw bits) for `e`, or the abort code that refuses it.
    virtual std::uint32_t check_download(const OdEntry& e, std::uint32_t value) = 0;
    // `e` now holds the new value.
    virtual void after_download(const OdEntry& e) = 0;
  };

  static constexpr std::size_t kMaxInjectedAborts = 8;
  static constexpr std::uint8_t kAnySubindex = 0xFF;  // inject_abort(): every subindex

  // Every access (upload or download) to index:subindex (kAnySubindex: any) is answered with
  // abort `code`, until clear_injected_aborts(). False when kMaxInjectedAborts are set.
  bool inject_abort(std::uint16_t index, std::uint8_t subindex, std::uint32_t code);
  void clear_injected_aborts() { injected_count_ = 0; }

  // One request (COB-ID 0x600 + node, 8 bytes); fills `resp` (COB-ID 0x580 + node) and returns
  // true when an answer is due (an abort from the client gets none).
  bool serve(const hal::CanFrame& req, ObjectDictionary& od, Hooks& hooks, hal::CanFrame& resp);

  std::uint64_t requests() const { return requests_; }
  std::uint64_t aborts_sent() const { return aborts_sent_; }
  // The last abort code sent (0: none yet).
  std::uint32_t last_abort() const { return last_abort_; }

 private:
  struct Injected {
    std::uint16_t index;
    std::uint8_t subindex;
    std::uint32_t code;
  };
  std::uint32_t injected_code(std::uint16_t index, std::uint8_t subindex) const;
  std::uint32_t download(const std::uint8_t* d, ObjectDictionary& od, Hooks& hooks);
  bool abort(hal::CanFrame& resp, std::uint32_t code);

  Injected injected_[kMaxInjectedAborts] = {};
  std::size_t injected_count_ = 0;
  std::uint64_t requests_ = 0;
  std::uint64_t aborts_sent_ = 0;
  std::uint32_t last_abort_ = 0;
};

}  // namespace carril::sim
