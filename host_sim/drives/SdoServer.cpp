#include "host_sim/drives/SdoServer.hpp"

#include "hal/canopen/Frames.hpp"
#include "hal/canopen/SdoClient.hpp"

namespace carril::sim {

using hal::CanFrame;
using hal::canopen::get_u16;
using hal::canopen::get_u32;
using hal::canopen::put_u32;

bool SdoServer::inject_abort(std::uint16_t index, std::uint8_t subindex, std::uint32_t code) {
  if (injected_count_ >= kMaxInjectedAborts) return false;
  injected_[injected_count_++] = Injected{index, subindex, code};
  return true;
}

std::uint32_t SdoServer::injected_code(std::uint16_t index, std::uint8_t subindex) const {
  for (std::size_t i = 0; i < injected_count_; ++i) {
    const Injected& j = injected_[i];
    if (j.index == index && (j.subindex == kAnySubindex || j.subindex == subindex)) return j.code;
  }
  return 0;
}

bool SdoServer::abort(CanFrame& resp, std::uint32_t code) {
  resp.data[0] = 0x80;
  put_u32(resp.data + 4, code);
  ++aborts_sent_;
  last_abort_ = code;
  return true;
}

std::uint32_t SdoServer::download(const std::uint8_t* d, ObjectDictionary& od, Hooks& hooks) {
  const std::uint16_t index = get_u16(d + 1);
  const std::uint8_t sub = d[3];
  // Expedited (bit 1) only: every object fits in 4 bytes, so a segmented request is a client
  // this server does not speak to.
  if ((d[0] & 0x02U) == 0) return kAbortBadCommand;
  OdEntry* e = od.find(index, sub);
  if (e == nullptr) return od.has_index(index) ? kAbortNoSubindex : kAbortNoObject;
  if (e->access != OdAccess::ReadWrite) return kAbortReadOnly;
  const std::uint8_t size = od_size(e->type);
  // Size indicated (bit 0): bits 2-3 count the unused bytes; unindicated: the object's size.
  if ((d[0] & 0x01U) != 0 && 4U - ((d[0] >> 2) & 0x03U) != size) return kAbortLength;
  std::uint32_t value = get_u32(d + 4);
  if (size < 4) value &= (1U << (8U * size)) - 1U;
  if (const std::uint32_t code = hooks.check_download(*e, value)) return code;
  e->value = value;
  hooks.after_download(*e);
  return 0;
}

bool SdoServer::serve(const CanFrame& req, ObjectDictionary& od, Hooks& hooks, CanFrame& resp) {
  ++requests_;
  resp = CanFrame{};
  resp.id = hal::kSdoResponseBase + od.node();
  resp.len = 8;
  const std::uint8_t* d = req.data;
  for (int i = 1; i < 4; ++i) resp.data[i] = d[i];  // index and subindex echoed
  const std::uint8_t ccs = d[0] >> 5;
  if (ccs == 4) return false;  // the client aborted: nothing to answer
  const std::uint16_t index = get_u16(d + 1);
  const std::uint8_t sub = d[3];
  if (ccs != 1 && ccs != 2) return abort(resp, kAbortBadCommand);
  if (const std::uint32_t code = injected_code(index, sub)) return abort(resp, code);
  if (ccs == 1) {
    if (const std::uint32_t code = download(d, od, hooks)) return abort(resp, code);
    resp.data[0] = 0x60;
    return true;
  }
  const OdEntry* e = od.find(index, sub);
  if (e == nullptr) return abort(resp, od.has_index(index) ? kAbortNoSubindex : kAbortNoObject);
  const std::uint8_t size = od_size(e->type);
  // Expedited upload response: 0x43 with n = 4 - size unused bytes in bits 2-3.
  resp.data[0] = static_cast<std::uint8_t>(0x43U | ((4U - size) << 2));
  put_u32(resp.data + 4, e->value);
  return true;
}

}  // namespace carril::sim
