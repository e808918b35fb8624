#pragma once
// A CiA 301 SDO client for one node, expedited transfers only (objects of 1, 2 or 4 bytes: the
// drive parameters a CANopen master sets at boot-up). A non-blocking state machine: start a
// transfer, hand it every received frame (on_frame) and the time (poll) each control tick, read
// the result once it is no longer Busy. No heap, no blocking; one transfer at a time.
#include <cstdint>

#include "hal/CanBus.hpp"
#include "hal/Types.hpp"

namespace carril::hal {

constexpr std::uint32_t kSdoRequestBase = 0x600U;   // client -> server COB-ID, + node id
constexpr std::uint32_t kSdoResponseBase = 0x580U;  // server -> client COB-ID, + node id

enum class SdoState : std::uint8_t {
  Idle,      // no transfer started yet
  Busy,      // request sent, waiting for the response
  Done,      // the server confirmed (download) or answered with a value (upload)
  Aborted,   // the server aborted; abort_code says why
  TimedOut,  // no valid response in time; the client sent abort 0x05040000
  Error,     // the client gave up (segmented response, request not sent); see message
};

// The state of the last transfer and, once it ended, its outcome.
struct SdoResult {
  // Longest message: node 127, a 10-digit value and the longest abort meaning, ~141 chars.
  static constexpr int kMaxText = 160;

  SdoState state = SdoState::Idle;
  std::uint32_t abort_code = 0;  // received (Aborted) or sent (TimedOut, Error); 0 otherwise
  std::uint32_t value = 0;       // upload: the value read, zero-extended; download: value sent
  std::uint8_t size = 0;         // value size [bytes], 1, 2 or 4
  char message[kMaxText] = {};   // "node 3: SDO download 0x6060:00 = 3 aborted: 0x06090030 ..."
};

class SdoClient {
 public:
  struct Config {
    std::uint8_t node_id = 1;        // server node, 1..127
    TimeNs timeout_ns = 50'000'000;  // response deadline after the first poll [ns]
  };

  // The client sends requests on `bus`; the caller routes received frames to on_frame().
  SdoClient(CanBus& bus, const Config& cfg);

  // Write `value` (its low size_bytes bytes, 1, 2 or 4) to index:subindex; false, nothing
  // started, while Busy or with a bad size; false with state Error when the send is refused.
  bool start_download(std::uint16_t index, std::uint8_t subindex, std::uint32_t value,
                      std::uint8_t size_bytes);
  // Read index:subindex (expedited: up to 4 bytes); false as for start_download.
  bool start_upload(std::uint16_t index, std::uint8_t subindex);
  // A received frame; frames not from this client's server are ignored, malformed or
  // mismatching responses are counted in protocol_errors() and otherwise ignored.
  void on_frame(const CanFrame& frame);
  // Advance time [ns]: arms the deadline on the first poll of a transfer, times it out after.
  void poll(TimeNs now);

  // The last transfer's state and outcome.
  const SdoResult& result() const { return result_; }
  // Whether a transfer is waiting for its response.
  bool busy() const { return result_.state == SdoState::Busy; }
  // Responses from this client's server that were malformed or did not fit the transfer
  // (wrong length, index, subindex or command specifier) since construction.
  std::uint32_t protocol_errors() const { return protocol_errors_; }
  // The server's node id, 1..127.
  std::uint8_t node_id() const { return cfg_.node_id; }

 private:
  enum class Kind : std::uint8_t { Download, Upload };

  bool start(Kind kind, std::uint16_t index, std::uint8_t subindex, std::uint32_t value,
             std::uint8_t size, std::uint8_t command);
  bool send_request(std::uint8_t command, std::uint32_t payload);
  void send_abort(std::uint32_t code);
  void finish(SdoState state, const char* what);

  CanBus& bus_;
  Config cfg_;
  SdoResult result_;
  Kind kind_ = Kind::Download;
  std::uint16_t index_ = 0;
  std::uint8_t subindex_ = 0;
  bool deadline_armed_ = false;
  TimeNs deadline_ = 0;
  std::uint32_t protocol_errors_ = 0;
};

}  // namespace carril::hal
