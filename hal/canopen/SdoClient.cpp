#include "hal/canopen/SdoClient.hpp"

#include <cstdio>

#include "hal/canopen/SdoAbort.hpp"

namespace carril::hal {

namespace {

// Command bytes (CiA 301 7.2.4.3): the top three bits are the command specifier; for the
// expedited initiate frames bits 3..2 hold n (unused data bytes), bit 1 e, bit 0 s.
constexpr std::uint8_t kCsMask = 0xE0U;
constexpr std::uint8_t kDownloadRequest = 0x23U;   // ccs 1, e 1, s 1; OR n << 2
constexpr std::uint8_t kDownloadResponse = 0x60U;  // scs 3
constexpr std::uint8_t kUploadRequest = 0x40U;     // ccs 2
constexpr std::uint8_t kUploadResponse = 0x40U;    // scs 2
constexpr std::uint8_t kAbort = 0x80U;             // cs 4, both directions
constexpr std::uint8_t kExpedited = 0x02U;         // e
constexpr std::uint8_t kSizeIndicated = 0x01U;     // s
constexpr std::uint8_t kSdoLen = 8;                // every SDO frame is 8 bytes long

std::uint32_t size_mask(std::uint8_t size) {
  return size >= 4 ? 0xFFFFFFFFU : (std::uint32_t{1} << (8U * size)) - 1U;
}

std::uint32_t read_le32(const std::uint8_t* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8U | std::uint32_t(p[2]) << 16U |
         std::uint32_t(p[3]) << 24U;
}

}  // namespace

SdoClient::SdoClient(CanBus& bus, const Config& cfg) : bus_(bus), cfg_(cfg) {}

bool SdoClient::start_download(std::uint16_t index, std::uint8_t subindex, std::uint32_t value,
                               std::uint8_t size_bytes) {
  if (size_bytes != 1 && size_bytes != 2 && size_bytes != 4) return false;
  const auto n = std::uint8_t(4U - size_bytes);
  return start(Kind::Download, index, subindex, value & size_mask(size_bytes), size_bytes,
               std::uint8_t(kDownloadRequest | n << 2U));
}

bool SdoClient::start_upload(std::uint16_t index, std::uint8_t subindex) {
  return start(Kind::Upload, index, subindex, 0, 0, kUploadRequest);
}

bool SdoClient::start(Kind kind, std::uint16_t index, std::uint8_t subindex, std::uint32_t value,
                      std::uint8_t size, std::uint8_t command) {
  // One transfer at a time: the server multiplexes nothing on one SDO channel either.
  if (busy() || cfg_.node_id < 1 || cfg_.node_id > 127) return false;
  kind_ = kind;
  index_ = index;
  subindex_ = subindex;
  deadline_armed_ = false;
  result_ = SdoResult{};
  result_.value = value;
  result_.size = size;
  if (!send_request(command, value)) {
    finish(SdoState::Error, "failed: request not sent (CAN transmit refused)");
    return false;
  }
  finish(SdoState::Busy, "busy");
  return true;
}

void SdoClient::on_frame(const CanFrame& f) {
  if (f.error || f.rtr || f.extended || f.id != kSdoResponseBase + cfg_.node_id) return;
  // From our server from here on: anything that does not fit the transfer is the server's (or
  // the bus's) fault, counted so a flaky node shows up, and ignored so the deadline decides.
  if (!busy() || f.len != kSdoLen) {
    ++protocol_errors_;
    return;
  }
  const std::uint8_t cmd = f.data[0];
  const auto index = std::uint16_t(f.data[1] | f.data[2] << 8U);
  const std::uint32_t payload = read_le32(&f.data[4]);
  if (index != index_ || f.data[3] != subindex_) {
    ++protocol_errors_;
    return;
  }
  if (cmd == kAbort) {
    result_.abort_code = payload;
    char what[SdoResult::kMaxText];
    std::snprintf(what, sizeof what, "aborted: 0x%08X %s", unsigned(payload),
                  sdo_abort_meaning(payload));
    finish(SdoState::Aborted, what);
    return;
  }
  if (kind_ == Kind::Download) {
    if ((cmd & kCsMask) != kDownloadResponse) {
      ++protocol_errors_;
      return;
    }
    finish(SdoState::Done, "done");
    return;
  }
  if ((cmd & kCsMask) != kUploadResponse) {
    ++protocol_errors_;
    return;
  }
  if ((cmd & kExpedited) == 0) {
    // The object is longer than 4 bytes and the server wants segments we do not speak: end
    // the transfer on its side too, or it would wait for our segment requests.
    send_abort(kSdoAbortBadCommand);
    result_.abort_code = kSdoAbortBadCommand;
    char what[SdoResult::kMaxText];
    std::snprintf(what, sizeof what,
                  "failed: segmented transfer not supported, sent abort 0x%08X %s",
                  unsigned(kSdoAbortBadCommand), sdo_abort_meaning(kSdoAbortBadCommand));
    finish(SdoState::Error, what);
    return;
  }
  // s = 0: size not indicated, the server filled all four bytes.
  const auto size =
      (cmd & kSizeIndicated) != 0 ? std::uint8_t(4U - ((cmd >> 2U) & 0x3U)) : std::uint8_t(4);
  result_.size = size;
  result_.value = payload & size_mask(size);
  finish(SdoState::Done, "done");
}

void SdoClient::poll(TimeNs now) {
  if (!busy()) return;
  // start_*() has no clock; the first poll of the transfer is at most one tick later, so the
  // deadline can only be late by that much, never early.
  if (!deadline_armed_) {
    deadline_ = now + cfg_.timeout_ns;
    deadline_armed_ = true;
    return;
  }
  if (now < deadline_) return;
  send_abort(kSdoAbortTimeout);
  result_.abort_code = kSdoAbortTimeout;
  char what[SdoResult::kMaxText];
  std::snprintf(what, sizeof what, "timed out after %lld ms, sent abort 0x%08X",
                static_cast<long long>(cfg_.timeout_ns / 1'000'000), unsigned(kSdoAbortTimeout));
  finish(SdoState::TimedOut, what);
}

bool SdoClient::send_request(std::uint8_t command, std::uint32_t payload) {
  CanFrame f;
  f.id = kSdoRequestBase + cfg_.node_id;
  f.len = kSdoLen;
  f.data[0] = command;
  f.data[1] = std::uint8_t(index_ & 0xFFU);
  f.data[2] = std::uint8_t(index_ >> 8U);
  f.data[3] = subindex_;
  for (unsigned i = 0; i < 4; ++i) f.data[4 + i] = std::uint8_t(payload >> (8U * i));
  return bus_.send(f);
}

void SdoClient::send_abort(std::uint32_t code) {
  // Best effort: if the transmit queue refuses it, the server's own timeout ends its side.
  (void)send_request(kAbort, code);
}

void SdoClient::finish(SdoState state, const char* what) {
  result_.state = state;
  const bool download = kind_ == Kind::Download;
  const bool show_value = download || state == SdoState::Done;
  char value[24] = {};
  if (show_value) std::snprintf(value, sizeof value, " = %u", unsigned(result_.value));
  std::snprintf(result_.message, sizeof result_.message, "node %u: SDO %s 0x%04X:%02X%s %s",
                unsigned(cfg_.node_id), download ? "download" : "upload", unsigned(index_),
                unsigned(subindex_), value, what);
}

}  // namespace carril::hal
