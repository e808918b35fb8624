#include "host_sim/drives/ObjectDictionary.hpp"

namespace carril::sim {

namespace {

constexpr OdType U8 = OdType::Unsigned8;
constexpr OdType U16 = OdType::Unsigned16;
constexpr OdType U32 = OdType::Unsigned32;
constexpr OdType I8 = OdType::Integer8;
constexpr OdType I16 = OdType::Integer16;
constexpr OdType I32 = OdType::Integer32;
constexpr OdAccess C = OdAccess::Const;
constexpr OdAccess RO = OdAccess::ReadOnly;
constexpr OdAccess RW = OdAccess::ReadWrite;

struct Def {
  std::uint16_t index;
  std::uint8_t subindex;
  OdType type;
  OdAccess access;
  std::uint32_t default_value;
  bool node_relative;
  bool pdo_mappable;
  const char* name;
};

// The drive's objects. Defaults are what a drive has after power-on: the PDOs already carry the
// fixed mapping of docs/can-protocol.md (the master rewrites it anyway), heartbeats are off
// until the master sets 0x1016/0x1017, and no mode of operation is selected.
constexpr Def kObjects[] = {
    {0x1000, 0, U32, C, 0x00020192U, false, false, "Device type"},  // CiA 402, servo drive
    {0x1001, 0, U8, RO, 0, false, false, "Error register"},
    {0x1016, 0, U8, C, 1, false, false, "Consumer heartbeat time: highest sub-index"},
    {0x1016, 1, U32, RW, 0, false, false, "Consumer heartbeat time 1"},
    {0x1017, 0, U16, RW, 0, false, false, "Producer heartbeat time"},
    {0x1018, 0, U8, C, 4, false, false, "Identity object: highest sub-index"},
    {0x1018, 1, U32, C, 0, false, false, "Vendor-ID"},
    {0x1018, 2, U32, C, 0x00402001U, false, false, "Product code"},
    {0x1018, 3, U32, C, 0x00010000U, false, false, "Revision number"},
    {0x1018, 4, U32, C, 0, true, false, "Serial number"},
    {0x1400, 0, U8, C, 2, false, false, "RPDO1 communication: highest sub-index"},
    {0x1400, 1, U32, RW, 0x200, true, false, "RPDO1 COB-ID"},
    {0x1400, 2, U8, RW, 1, false, false, "RPDO1 transmission type"},
    {0x1600, 0, U8, RW, 2, false, false, "RPDO1 mapping: number of objects"},
    {0x1600, 1, U32, RW, 0x60400010U, false, false, "RPDO1 mapping entry 1"},
    {0x1600, 2, U32, RW, 0x60FF0020U, false, false, "RPDO1 mapping entry 2"},
    {0x1800, 0, U8, C, 2, false, false, "TPDO1 communication: highest sub-index"},
    {0x1800, 1, U32, RW, 0x180, true, false, "TPDO1 COB-ID"},
    {0x1800, 2, U8, RW, 1, false, false, "TPDO1 transmission type"},
    {0x1801, 0, U8, C, 2, false, false, "TPDO2 communication: highest sub-index"},
    {0x1801, 1, U32, RW, 0x280, true, false, "TPDO2 COB-ID"},
    {0x1801, 2, U8, RW, 1, false, false, "TPDO2 transmission type"},
    {0x1A00, 0, U8, RW, 2, false, false, "TPDO1 mapping: number of objects"},
    {0x1A00, 1, U32, RW, 0x60410010U, false, false, "TPDO1 mapping entry 1"},
    {0x1A00, 2, U32, RW, 0x606C0020U, false, false, "TPDO1 mapping entry 2"},
    {0x1A01, 0, U8, RW, 1, false, false, "TPDO2 mapping: number of objects"},
    {0x1A01, 1, U32, RW, 0x60640020U, false, false, "TPDO2 mapping entry 1"},
    {0x603F, 0, U16, RO, 0, false, false, "Error code"},
    {0x6040, 0, U16, RW, 0, false, true, "Controlword"},
    {0x6041, 0, U16, RO, 0, false, true, "Statusword"},
    {0x605A, 0, I16, RW, 2, false, false, "Quick stop option code"},
    {0x6060, 0, I8, RW, 0, false, false, "Modes of operation"},
    {0x6061, 0, I8, RO, 0, false, false, "Modes of operation display"},
    {0x6064, 0, I32, RO, 0, false, true, "Position actual value"},
    {0x606B, 0, I32, RO, 0, false, false, "Velocity demand value"},
    {0x606C, 0, I32, RO, 0, false, true, "Velocity actual value"},
    {0x6083, 0, U32, RW, 40960, false, false, "Profile acceleration"},
    {0x6084, 0, U32, RW, 40960, false, false, "Profile deceleration"},
    {0x6085, 0, U32, RW, 81920, false, false, "Quick stop deceleration"},
    {0x60FF, 0, I32, RW, 0, false, true, "Target velocity"},
    {0x6502, 0, U32, C, 0x00000004U, false, false, "Supported drive modes"},  // bit 2: pv
};
static_assert(sizeof(kObjects) / sizeof(kObjects[0]) <= ObjectDictionary::kMaxEntries);

}  // namespace

std::uint8_t od_size(OdType t) {
  switch (t) {
    case OdType::Integer8:
    case OdType::Unsigned8:
      return 1;
    case OdType::Integer16:
    case OdType::Unsigned16:
      return 2;
    case OdType::Integer32:
    case OdType::Unsigned32:
      return 4;
  }
  return 4;
}

const char* od_access_name(OdAccess a) {
  switch (a) {
    case OdAccess::Const:
      return "const";
    case OdAccess::ReadOnly:
      return "ro";
    case OdAccess::ReadWrite:
      return "rw";
  }
  return "ro";
}

ObjectDictionary::ObjectDictionary(std::uint8_t node) : node_(node) {
  for (const Def& d : kObjects) {
    OdEntry& e = entries_[count_++];
    e.index = d.index;
    e.subindex = d.subindex;
    e.type = d.type;
    e.access = d.access;
    e.default_value = d.default_value;
    e.node_relative = d.node_relative;
    e.pdo_mappable = d.pdo_mappable;
    e.name = d.name;
  }
  reset_all();
}

void ObjectDictionary::reset_range(std::uint16_t first, std::uint16_t last) {
  for (std::size_t i = 0; i < count_; ++i) {
    OdEntry& e = entries_[i];
    if (e.index < first || e.index > last) continue;
    e.value = default_value(e.index, e.subindex);
  }
}

void ObjectDictionary::reset_all() {
  reset_range(0x0000, 0xFFFF);
}

void ObjectDictionary::reset_communication() {
  reset_range(0x1000, 0x1FFF);
}

OdEntry* ObjectDictionary::find(std::uint16_t index, std::uint8_t subindex) {
  for (std::size_t i = 0; i < count_; ++i) {
    if (entries_[i].index == index && entries_[i].subindex == subindex) return &entries_[i];
  }
  return nullptr;
}

const OdEntry* ObjectDictionary::find(std::uint16_t index, std::uint8_t subindex) const {
  return const_cast<ObjectDictionary*>(this)->find(index, subindex);
}

bool ObjectDictionary::has_index(std::uint16_t index) const {
  for (std::size_t i = 0; i < count_; ++i) {
    if (entries_[i].index == index) return true;
  }
  return false;
}

std::uint32_t ObjectDictionary::get(std::uint16_t index, std::uint8_t subindex) const {
  const OdEntry* e = find(index, subindex);
  return e != nullptr ? e->value : 0U;
}

std::uint32_t ObjectDictionary::default_value(std::uint16_t index, std::uint8_t subindex) const {
  const OdEntry* e = find(index, subindex);
  return e != nullptr ? e->default_value + (e->node_relative ? node_ : 0U) : 0U;
}

void ObjectDictionary::set(std::uint16_t index, std::uint8_t subindex, std::uint32_t value) {
  if (OdEntry* e = find(index, subindex)) {
    const std::uint8_t n = od_size(e->type);
    e->value = n == 4 ? value : value & ((1U << (8U * n)) - 1U);
  }
}

}  // namespace carril::sim
