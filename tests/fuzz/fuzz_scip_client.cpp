// Fuzz target: the SCIP 2.0 client side (hal/scip/ScipCodec as hal/linux/ScipLidar uses it). The
// input is the byte stream a sensor sends: it is cut into messages as ScipLidar's session does
// (leading empty lines skipped, a message ends with an empty line), and each message is decoded
// by what its echo names: PP into the scan geometry, VV and II as info replies, anything else as
// a distance message (ranges and ME intensities), whose values become ranges [m] as the lidar
// publishes them. Every line is also parsed as a command (the server side, hal/scip's other half).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string_view>

#include "FuzzTempFiles.hpp"
#include "hal/Types.hpp"
#include "hal/scip/ScipCodec.hpp"

namespace scip = carril::hal::scip;

namespace {

struct Buffers {
  scip::Lines lines;
  std::uint32_t ranges[carril::hal::kMaxScanBeams];
  std::uint32_t intensities[carril::hal::kMaxScanBeams];
};

void decode_message(std::string_view msg, Buffers& b, scip::Geometry& g) {
  if (!scip::split_lines(msg.data(), msg.size(), b.lines)) return;
  for (int i = 0; i < b.lines.count; ++i) {
    const scip::Request r = scip::parse_request(b.lines.text[i], b.lines.len[i]);
    if (strnlen(r.tag, sizeof r.tag) == sizeof r.tag) std::abort();  // unterminated tag
  }
  const char* why = "";
  if (msg.size() >= 2 && msg[0] == 'P' && msg[1] == 'P') {
    scip::Geometry next;
    if (scip::parse_pp(b.lines, next, why) && next.complete()) g = next;
    return;
  }
  char value[32];
  if (msg.size() >= 2 && msg[0] == 'V' && msg[1] == 'V') {
    scip::parse_info_reply(b.lines, scip::Command::VV, "PROD", value, sizeof value, why);
    return;
  }
  if (msg.size() >= 2 && msg[0] == 'I' && msg[1] == 'I') {
    scip::parse_info_reply(b.lines, scip::Command::II, "STAT", value, sizeof value, why);
    return;
  }
  scip::Distances d;
  const scip::ReplyError e =
      scip::parse_distances(b.lines, b.ranges, b.intensities, carril::hal::kMaxScanBeams, d);
  if (std::strlen(scip::reply_error_text(e)) == 0) std::abort();
  if (e != scip::ReplyError::None || !d.has_data) return;
  if (d.count < 0 || d.count > carril::hal::kMaxScanBeams) std::abort();
  for (int i = 0; i < d.count; ++i) (void)scip::wire_to_range(b.ranges[i], g.dmin_mm);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto buffers = std::make_unique<Buffers>();
  scip::Geometry g;
  g.dmin_mm = 20;  // until a PP reply says otherwise
  std::string_view rest = carril::fuzz::as_text(data, size);
  for (;;) {
    while (!rest.empty() && rest.front() == '\n') rest.remove_prefix(1);
    const std::size_t end = rest.find("\n\n");
    if (end == std::string_view::npos) break;
    decode_message(rest.substr(0, end + 2), *buffers, g);
    rest.remove_prefix(end + 2);
  }
  return 0;
}
