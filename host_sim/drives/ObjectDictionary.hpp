#pragma once
// The object dictionary of the emulated CiA 402 drive: exactly the objects it implements (those
// the master of docs/can-protocol.md reads and writes, and the mandatory CiA 301 ones), each
// with its data type, access and default. config/drives/carril_emulated_drive.eds describes the
// same table (a test compares them). Fixed size: no heap.
#include <cstddef>
#include <cstdint>

namespace carril::sim {

// CiA 301 data types (their EDS DataType codes).
enum class OdType : std::uint16_t {
  Integer8 = 0x0002,
  Integer16 = 0x0003,
  Integer32 = 0x0004,
  Unsigned8 = 0x0005,
  Unsigned16 = 0x0006,
  Unsigned32 = 0x0007,
};
// Size of a value of type t [bytes]: 1, 2 or 4.
std::uint8_t od_size(OdType t);

// EDS AccessType: const and ro refuse SDO downloads (abort 0x06010002).
enum class OdAccess : std::uint8_t { Const, ReadOnly, ReadWrite };
const char* od_access_name(OdAccess a);  // "const", "ro", "rw" as an EDS writes them

// One object (index, subindex) and its value.
struct OdEntry {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  OdType type = OdType::Unsigned8;
  OdAccess access = OdAccess::ReadOnly;
  std::uint32_t default_value = 0;  // raw bits, zero-extended; + node id when node_relative
  bool node_relative = false;       // EDS DefaultValue "$NODEID+..." (COB-IDs, serial number)
  bool pdo_mappable = false;        // EDS PDOMapping=1
  const char* name = "";            // EDS ParameterName
  std::uint32_t value = 0;          // current value, raw bits (signed types: two's complement)
};

class ObjectDictionary {
 public:
  static constexpr std::size_t kMaxEntries = 48;

  // The table with every value at its default for node `node` (1 to 127).
  explicit ObjectDictionary(std::uint8_t node);

  // NMT reset node (and power-on): every object to its default.
  void reset_all();
  // NMT reset communication: the communication area 0x1000-0x1FFF to its defaults.
  void reset_communication();

  // The object index:subindex, or nullptr.
  OdEntry* find(std::uint16_t index, std::uint8_t subindex);
  const OdEntry* find(std::uint16_t index, std::uint8_t subindex) const;
  // Whether any subindex of `index` exists (tells abort 0x06020000 from 0x06090011).
  bool has_index(std::uint16_t index) const;

  // Current raw value of an object the emulator knows exists (0 when it does not).
  std::uint32_t get(std::uint16_t index, std::uint8_t subindex) const;
  // The default of an object (node id added where node-relative), 0 when it does not exist.
  std::uint32_t default_value(std::uint16_t index, std::uint8_t subindex) const;
  // Sets an object's value without any SDO check (the drive's own updates, e.g. 0x6041).
  void set(std::uint16_t index, std::uint8_t subindex, std::uint32_t value);

  std::size_t size() const { return count_; }
  const OdEntry& entry(std::size_t i) const { return entries_[i]; }
  std::uint8_t node() const { return node_; }

 private:
  void reset_range(std::uint16_t first, std::uint16_t last);

  OdEntry entries_[kMaxEntries];
  std::size_t count_ = 0;
  std::uint8_t node_ = 1;
};

}  // namespace carril::sim
