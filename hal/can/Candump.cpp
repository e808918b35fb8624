#include "hal/can/Candump.hpp"

#include <cstdio>
#include <cstring>

namespace carril::hal {

namespace {
constexpr std::uint32_t kErrFlag = 0x20000000U;  // SocketCAN's CAN_ERR_FLAG
constexpr char kHex[] = "0123456789ABCDEF";

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

// Whole seconds a TimeNs holds with any microseconds added (2^63 ns: the year 2262).
constexpr long long kMaxStampSec = 9'223'372'035LL;

// The "(seconds.microseconds)" stamp at the start of a line (spaces before it allowed), as
// candump writes it: up to 6 fraction digits, read as microseconds as can-utils' readers do. False
// for anything else: a sign, a missing ')', or a time beyond TimeNs (its nanoseconds would
// overflow). On success p is just past the ')'.
bool parse_stamp(const char*& p, TimeNs& t_ns) {
  while (*p == ' ' || *p == '\t') ++p;
  if (*p++ != '(') return false;
  long long sec = 0;
  int digits = 0;
  for (; *p >= '0' && *p <= '9'; ++p, ++digits) {
    sec = sec * 10 + (*p - '0');
    if (sec > kMaxStampSec) return false;
  }
  if (digits == 0 || *p++ != '.') return false;
  long long usec = 0;
  digits = 0;
  for (; *p >= '0' && *p <= '9'; ++p, ++digits) {
    if (digits == 6) return false;
    usec = usec * 10 + (*p - '0');
  }
  if (digits == 0 || *p++ != ')') return false;
  t_ns = TimeNs(sec) * 1'000'000'000 + TimeNs(usec) * 1000;
  return true;
}
}  // namespace

std::size_t format_candump(const CanFrame& f, TimeNs t_ns, const char* iface, char* buf,
                           std::size_t n) {
  const long long sec = t_ns / 1'000'000'000;
  const long long usec = (t_ns % 1'000'000'000) / 1000;
  const std::uint32_t id = f.error ? (kErrFlag | (f.id & kCanExtIdMask)) : f.id;
  const bool long_id = f.extended || f.error;
  int k = std::snprintf(buf, n, "(%lld.%06lld) %s %0*X#", sec, usec, iface, long_id ? 8 : 3,
                        unsigned(long_id ? id : (id & kCanStdIdMask)));
  if (k < 0 || std::size_t(k) >= n) return 0;
  std::size_t len = std::size_t(k);
  const std::size_t need = f.rtr ? 3 : std::size_t(f.len) * 2;
  if (len + need + 1 > n) return 0;
  if (f.rtr) {
    buf[len++] = 'R';
    if (f.len > 0) buf[len++] = char('0' + (f.len > kCanMaxLen ? kCanMaxLen : f.len));
  } else {
    for (std::uint8_t i = 0; i < f.len && i < kCanMaxLen; ++i) {
      buf[len++] = kHex[f.data[i] >> 4];
      buf[len++] = kHex[f.data[i] & 0xF];
    }
  }
  buf[len] = '\0';
  return len;
}

bool parse_candump(const char* line, CanFrame& out, TimeNs& t_ns) {
  const char* p = line;
  TimeNs stamp = 0;
  if (!parse_stamp(p, stamp)) return false;
  while (*p == ' ') ++p;
  while (*p != ' ' && *p != '\0') ++p;  // interface name
  while (*p == ' ') ++p;
  const char* hash = std::strchr(p, '#');
  if (hash == nullptr) return false;
  const std::size_t id_len = std::size_t(hash - p);
  if (id_len != 3 && id_len != 8) return false;
  std::uint32_t id = 0;
  for (std::size_t i = 0; i < id_len; ++i) {
    const int v = hex_value(p[i]);
    if (v < 0) return false;
    id = (id << 4) | std::uint32_t(v);
  }
  CanFrame f;
  f.extended = id_len == 8;
  f.error = f.extended && (id & kErrFlag) != 0;
  f.id = f.extended ? (id & kCanExtIdMask) : id;
  if (!f.extended && id > kCanStdIdMask) return false;
  const char* d = hash + 1;
  if (*d == 'R') {
    f.rtr = true;
    const int len = d[1] >= '0' && d[1] <= '8' ? d[1] - '0' : 0;
    f.len = std::uint8_t(len);
  } else {
    std::uint8_t len = 0;
    while (hex_value(d[0]) >= 0) {
      if (hex_value(d[1]) < 0 || len >= kCanMaxLen) return false;  // odd digits or too long
      f.data[len++] = std::uint8_t(hex_value(d[0]) * 16 + hex_value(d[1]));
      d += 2;
    }
    if (*d != '\0' && *d != '\n' && *d != '\r' && *d != ' ') return false;
    f.len = len;
  }
  if (f.error) f.extended = false;  // an error frame is reported, not an extended data frame
  out = f;
  t_ns = stamp;
  return true;
}

}  // namespace carril::hal
