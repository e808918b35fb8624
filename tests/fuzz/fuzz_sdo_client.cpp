// Fuzz target: the SDO client (hal/canopen/SdoClient) against a server that answers anything.
// The input is a script: each step a command byte, then its arguments:
//   0 start a download (index, subindex, value, size), 1 start an upload (index, subindex),
//   2 a frame from the server's COB-ID (the filter passed: what the decoding does with it),
//   3 any frame (FuzzFrames.hpp), 4 time passes (2 bytes [ms]).
// The client's requests go over a LoopbackCanBus to a second endpoint, drained every step and
// checked: a request is always an 8-byte frame to 0x600 + node.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "FuzzFrames.hpp"
#include "hal/can/LoopbackCanBus.hpp"
#include "hal/canopen/SdoClient.hpp"

using carril::hal::CanFrame;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  carril::fuzz::ByteReader in(data, size);
  carril::hal::LoopbackCanBus bus({});
  carril::hal::SdoClient::Config cfg;
  cfg.node_id = static_cast<std::uint8_t>(in.u8() % 127 + 1);
  carril::hal::SdoClient client(bus.endpoint(0), cfg);
  carril::hal::CanBus& server = bus.endpoint(1);
  carril::hal::TimeNs now = 0;
  int steps = 0;
  while (in.remaining() > 0 && ++steps < 4096) {
    switch (in.u8() % 5) {
      case 0: {
        const auto index = in.u16();
        const auto sub = in.u8();
        const auto value = in.u32();
        client.start_download(index, sub, value, in.u8() % 6);
        break;
      }
      case 1: {
        const auto index = in.u16();
        client.start_upload(index, in.u8());
        break;
      }
      case 2: {
        CanFrame f = carril::fuzz::read_frame(in);
        f.id = carril::hal::kSdoResponseBase + cfg.node_id;
        f.extended = f.rtr = f.error = false;
        client.on_frame(f);
        break;
      }
      case 3:
        client.on_frame(carril::fuzz::read_frame(in));
        break;
      default:
        now += carril::hal::TimeNs{in.u16()} * 1'000'000;
        client.poll(now);
        break;
    }
    bus.transfer();
    CanFrame sent;
    while (server.receive(sent)) {
      if (sent.id != carril::hal::kSdoRequestBase + cfg.node_id || sent.len != 8) std::abort();
    }
    const carril::hal::SdoResult& r = client.result();
    if (strnlen(r.message, sizeof r.message) == sizeof r.message) std::abort();
  }
  return 0;
}
