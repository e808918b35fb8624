#include "hal/scip/ScipCodec.hpp"

#include <cmath>
#include <cstring>
#include <limits>

namespace carril::hal::scip {

namespace {

constexpr char kOffset = 0x30;

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

// Fixed-width decimal field at s[0..width); false when a character is not a digit or missing.
bool read_dec(const char* s, std::size_t avail, int width, int& out) {
  if (avail < std::size_t(width)) return false;
  int v = 0;
  for (int i = 0; i < width; ++i) {
    if (!is_digit(s[i])) return false;
    v = v * 10 + (s[i] - '0');
  }
  out = v;
  return true;
}

// Fixed-width decimal (zero padded) into out; the value must fit in width digits.
void write_dec(int v, int width, char* out) {
  for (int i = width - 1; i >= 0; --i) {
    out[i] = char('0' + v % 10);
    v /= 10;
  }
}

bool is_data_command(Command c) {
  return c == Command::MD || c == Command::MS || c == Command::GD || c == Command::GS ||
         c == Command::ME;
}
bool is_continuous(Command c) {
  return c == Command::MD || c == Command::MS || c == Command::ME;
}

Command command_of(char a, char b) {
  struct Entry {
    char a, b;
    Command c;
  };
  static constexpr Entry kTable[] = {
      {'M', 'D', Command::MD}, {'M', 'S', Command::MS}, {'G', 'D', Command::GD},
      {'G', 'S', Command::GS}, {'M', 'E', Command::ME}, {'V', 'V', Command::VV},
      {'P', 'P', Command::PP}, {'I', 'I', Command::II}, {'B', 'M', Command::BM},
      {'Q', 'T', Command::QT}, {'R', 'S', Command::RS},
  };
  for (const Entry& e : kTable)
    if (e.a == a && e.b == b) return e.c;
  return Command::Unknown;
}

const char* letters_of(Command c) {
  switch (c) {
    case Command::MD:
      return "MD";
    case Command::MS:
      return "MS";
    case Command::GD:
      return "GD";
    case Command::GS:
      return "GS";
    case Command::ME:
      return "ME";
    case Command::VV:
      return "VV";
    case Command::PP:
      return "PP";
    case Command::II:
      return "II";
    case Command::BM:
      return "BM";
    case Command::QT:
      return "QT";
    case Command::RS:
      return "RS";
    case Command::Unknown:
      break;
  }
  return nullptr;
}

void set_status(Request& r, const char* s) {
  r.status[0] = s[0];
  r.status[1] = s[1];
}

// Characters per value and values per step for a data command.
int value_chars(Command c) {
  return c == Command::MS || c == Command::GS ? 2 : 3;
}

}  // namespace

bool encode(std::uint32_t value, int chars, char* out) {
  if (chars < 1 || chars > 4 || value > max_encodable(chars)) return false;
  for (int i = chars - 1; i >= 0; --i) {
    out[i] = char(kOffset + (value & 0x3FU));
    value >>= 6;
  }
  return true;
}

bool decode(const char* in, int chars, std::uint32_t& value) {
  std::uint32_t v = 0;
  for (int i = 0; i < chars; ++i) {
    const int c = static_cast<unsigned char>(in[i]) - kOffset;
    if (c < 0 || c > 0x3F) return false;
    v = (v << 6) | std::uint32_t(c);
  }
  value = v;
  return true;
}

char checksum(const char* s, std::size_t n) {
  unsigned sum = 0;
  for (std::size_t i = 0; i < n; ++i) sum += static_cast<unsigned char>(s[i]);
  return char((sum & 0x3FU) + unsigned(kOffset));
}

bool line_sum_ok(const char* line, std::size_t n) {
  return n >= 2 && checksum(line, n - 1) == line[n - 1];
}

bool parse_status(const char* line, std::size_t n, char status[2]) {
  if (n != 3 || !line_sum_ok(line, n)) return false;
  status[0] = line[0];
  status[1] = line[1];
  return true;
}

Request parse_request(const char* line, std::size_t n) {
  Request r;
  if (n < 2) {
    set_status(r, kStatusUnknown);
    return r;
  }
  r.code[0] = line[0];
  r.code[1] = line[1];
  r.cmd = command_of(line[0], line[1]);
  // The tag runs from ';' to the end of the line.
  std::size_t body_end = n;
  for (std::size_t i = 2; i < n; ++i) {
    if (line[i] == ';') {
      body_end = i;
      std::size_t t = 0;
      for (std::size_t j = i + 1; j < n && t < std::size_t(kMaxTagChars); ++j) r.tag[t++] = line[j];
      r.tag[t] = '\0';
      break;
    }
  }
  if (r.cmd == Command::Unknown) {
    set_status(r, kStatusUnknown);
    return r;
  }
  if (!is_data_command(r.cmd)) return r;
  const char* p = line + 2;
  std::size_t avail = body_end - 2;
  if (!read_dec(p, avail, 4, r.start_step)) return set_status(r, kStatusBadStart), r;
  if (!read_dec(p + 4, avail - 4, 4, r.end_step)) return set_status(r, kStatusBadEnd), r;
  if (!read_dec(p + 8, avail - 8, 2, r.cluster)) return set_status(r, kStatusBadCluster), r;
  if (is_continuous(r.cmd)) {
    if (!read_dec(p + 10, avail - 10, 1, r.interval)) return set_status(r, kStatusBadInterval), r;
    if (!read_dec(p + 11, avail - 11, 2, r.scans) || avail != 13)
      return set_status(r, kStatusBadScans), r;
  } else if (avail != 10) {
    return set_status(r, kStatusBadCluster), r;
  }
  if (r.end_step < r.start_step) set_status(r, kStatusEndBeforeStart);
  return r;
}

std::size_t format_data_request(Command cmd, int start_step, int end_step, int cluster,
                                int interval, int scans, char* out, std::size_t cap) {
  const char* letters = letters_of(cmd);
  if (!is_data_command(cmd) || letters == nullptr) return 0;
  const bool cont = is_continuous(cmd);
  const std::size_t len = cont ? 16 : 13;  // letters, fields, LF
  if (cap < len || start_step < 0 || start_step > 9999 || end_step < 0 || end_step > 9999 ||
      cluster < 0 || cluster > 99 || interval < 0 || interval > 9 || scans < 0 || scans > 99)
    return 0;
  out[0] = letters[0];
  out[1] = letters[1];
  write_dec(start_step, 4, out + 2);
  write_dec(end_step, 4, out + 6);
  write_dec(cluster, 2, out + 10);
  if (cont) {
    write_dec(interval, 1, out + 12);
    write_dec(scans, 2, out + 13);
  }
  out[len - 1] = '\n';
  return len;
}

std::size_t format_simple_request(Command cmd, char* out, std::size_t cap) {
  const char* letters = letters_of(cmd);
  if (letters == nullptr || is_data_command(cmd) || cap < 3) return 0;
  out[0] = letters[0];
  out[1] = letters[1];
  out[2] = '\n';
  return 3;
}

// --- ReplyWriter ---

bool ReplyWriter::put(const char* s, std::size_t n) {
  if (!ok_ || cap_ - len_ < n) return ok_ = false;
  std::memcpy(buf_ + len_, s, n);
  len_ += n;
  return true;
}

bool ReplyWriter::echo(const Request& r, int remaining) {
  char line[2 + 13 + 1 + kMaxTagChars + 1];
  std::size_t n = 0;
  line[n++] = r.code[0];
  line[n++] = r.code[1];
  if (is_data_command(r.cmd)) {
    write_dec(r.start_step, 4, line + n);
    write_dec(r.end_step, 4, line + n + 4);
    write_dec(r.cluster, 2, line + n + 8);
    n += 10;
    if (is_continuous(r.cmd)) {
      write_dec(r.interval, 1, line + n);
      write_dec(remaining >= 0 ? remaining : r.scans, 2, line + n + 1);
      n += 3;
    }
  }
  if (r.tag[0] != '\0') {
    line[n++] = ';';
    for (int i = 0; r.tag[i] != '\0'; ++i) line[n++] = r.tag[i];
  }
  line[n++] = '\n';
  return put(line, n);
}

bool ReplyWriter::raw_line(const char* text, std::size_t n) {
  return put(text, n) && put("\n", 1);
}

bool ReplyWriter::status(const char code[2]) {
  const char line[4] = {code[0], code[1], checksum(code, 2), '\n'};
  return put(line, 4);
}

bool ReplyWriter::info(const char* key, const char* value) {
  char line[kMaxLine + 2];
  const std::size_t kl = std::strlen(key), vl = std::strlen(value);
  if (kl + vl + 4 > sizeof line) return ok_ = false;
  std::memcpy(line, key, kl);
  line[kl] = ':';
  std::memcpy(line + kl + 1, value, vl);
  const std::size_t body = kl + 1 + vl;
  line[body] = ';';
  line[body + 1] = checksum(line, body);
  line[body + 2] = '\n';
  return put(line, body + 3);
}

bool ReplyWriter::timestamp(std::uint32_t ms) {
  char line[6];
  encode(ms & max_encodable(4), 4, line);
  line[4] = checksum(line, 4);
  line[5] = '\n';
  return put(line, 6);
}

bool ReplyWriter::data(const std::uint32_t* values, int count, int chars) {
  // The encoding's widths only: any other would read past enc (clang-analyzer found it).
  if (chars < 1 || chars > 4) return ok_ = false;
  char line[kMaxDataLine + 2];
  int fill = 0;
  for (int i = 0; i < count; ++i) {
    char enc[4];
    const std::uint32_t v = values[i] > max_encodable(chars) ? max_encodable(chars) : values[i];
    if (!encode(v, chars, enc)) return ok_ = false;
    for (int c = 0; c < chars; ++c) {
      line[fill++] = enc[c];
      if (fill == kMaxDataLine) {
        line[fill] = checksum(line, std::size_t(fill));
        line[fill + 1] = '\n';
        if (!put(line, std::size_t(fill) + 2)) return false;
        fill = 0;
      }
    }
  }
  if (fill > 0) {
    line[fill] = checksum(line, std::size_t(fill));
    line[fill + 1] = '\n';
    return put(line, std::size_t(fill) + 2);
  }
  return ok_;
}

bool ReplyWriter::end() {
  return put("\n", 1);
}

// --- Reading replies ---

bool split_lines(const char* msg, std::size_t n, Lines& out) {
  out.count = 0;
  std::size_t start = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (msg[i] != '\n') continue;
    if (i == start) return i + 1 == n;  // the empty line ends the message
    if (out.count == Lines::kMax) return false;
    out.text[out.count] = msg + start;
    out.len[out.count] = i - start;
    ++out.count;
    start = i + 1;
  }
  return false;
}

const char* reply_error_text(ReplyError e) {
  switch (e) {
    case ReplyError::None:
      return "ok";
    case ReplyError::Truncated:
      return "data shorter or longer than the echo asks for";
    case ReplyError::BadChecksum:
      return "checksum mismatch";
    case ReplyError::BadEcho:
      return "echo is not a well-formed data command";
    case ReplyError::BadStatus:
      return "error status";
    case ReplyError::BadEncoding:
      return "character outside the encoding";
    case ReplyError::TooLong:
      return "more values than the buffer holds";
  }
  return "unknown";
}

ReplyError parse_distances(const Lines& lines, std::uint32_t* ranges, std::uint32_t* intensities,
                           int cap, Distances& out) {
  out = Distances{};
  if (lines.count < 2) return ReplyError::Truncated;
  out.echo = parse_request(lines.text[0], lines.len[0]);
  if (!is_data_command(out.echo.cmd) || out.echo.status[0] != '0' || out.echo.status[1] != '0')
    return ReplyError::BadEcho;
  if (!parse_status(lines.text[1], lines.len[1], out.status)) return ReplyError::BadChecksum;
  const bool ok00 = out.status[0] == '0' && out.status[1] == '0';
  const bool ok99 = out.status[0] == '9' && out.status[1] == '9';
  if (!ok00 && !ok99) return ReplyError::BadStatus;
  if (ok00 && is_continuous(out.echo.cmd)) {
    // MD acknowledgement: no data may follow.
    return lines.count == 2 ? ReplyError::None : ReplyError::Truncated;
  }
  if (lines.count < 3) return ReplyError::Truncated;
  if (lines.len[2] != 5 || !line_sum_ok(lines.text[2], 5)) return ReplyError::BadChecksum;
  if (!decode(lines.text[2], 4, out.stamp_ms)) return ReplyError::BadEncoding;

  const int cluster = out.echo.cluster > 1 ? out.echo.cluster : 1;
  const int steps = out.echo.end_step - out.echo.start_step + 1;
  const int expected = (steps + cluster - 1) / cluster;
  if (expected > cap) return ReplyError::TooLong;
  const int chars = value_chars(out.echo.cmd);
  const bool me = out.echo.cmd == Command::ME;
  const int group = me ? 2 * chars : chars;  // characters per step
  char part[6];
  int have = 0;  // characters of the current step gathered so far (they may span two lines)
  int count = 0;
  for (int l = 3; l < lines.count; ++l) {
    const char* t = lines.text[l];
    const std::size_t n = lines.len[l];
    if (n < 2 || n > std::size_t(kMaxDataLine) + 1 || !line_sum_ok(t, n))
      return ReplyError::BadChecksum;
    for (std::size_t i = 0; i + 1 < n; ++i) {
      part[have++] = t[i];
      if (have < group) continue;
      have = 0;
      if (count == expected) return ReplyError::Truncated;
      std::uint32_t v = 0;
      if (!decode(part, chars, v)) return ReplyError::BadEncoding;
      ranges[count] = v;
      if (me) {
        if (!decode(part + chars, chars, v)) return ReplyError::BadEncoding;
        if (intensities != nullptr) intensities[count] = v;
      }
      ++count;
    }
  }
  if (have != 0 || count != expected) return ReplyError::Truncated;
  out.has_data = true;
  out.count = count;
  return ReplyError::None;
}

// --- Parameters ---

bool Geometry::complete() const {
  return dmin_mm > 0 && dmin_mm < dmax_mm && ares > 0 && amin >= 0 && amin <= afrt &&
         afrt <= amax && amax < ares + amin && scan_rpm > 0;
}

bool parse_info(const char* line, std::size_t n, const char*& key, std::size_t& key_len,
                const char*& value, std::size_t& value_len) {
  // "KEY:value;s": the sum is over "KEY:value", the ';' always second to last (the sum itself
  // may be a ';').
  if (n < 4 || line[n - 2] != ';' || checksum(line, n - 2) != line[n - 1]) return false;
  const char* colon = static_cast<const char*>(std::memchr(line, ':', n - 2));
  if (colon == nullptr) return false;
  key = line;
  key_len = std::size_t(colon - line);
  value = colon + 1;
  value_len = n - 2 - key_len - 1;
  return true;
}

namespace {
bool key_is(const char* key, std::size_t len, const char* want) {
  return std::strlen(want) == len && std::memcmp(key, want, len) == 0;
}
bool read_int(const char* s, std::size_t n, int& out) {
  if (n == 0 || n > 9) return false;
  int v = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!is_digit(s[i])) return false;
    v = v * 10 + (s[i] - '0');
  }
  out = v;
  return true;
}
bool header_ok(const Lines& lines, Command cmd, const char*& why) {
  if (lines.count < 2) return why = "reply too short", false;
  const Request echo = parse_request(lines.text[0], lines.len[0]);
  if (echo.cmd != cmd) return why = "echo does not match the command", false;
  char st[2];
  if (!parse_status(lines.text[1], lines.len[1], st)) return why = "status line sum wrong", false;
  if (st[0] != '0' || st[1] != '0') return why = "status not 00", false;
  return true;
}
}  // namespace

bool parse_pp(const Lines& lines, Geometry& g, const char*& why) {
  if (!header_ok(lines, Command::PP, why)) return false;
  g = Geometry{};
  struct Field {
    const char* key;
    int* dst;
  };
  const Field fields[] = {{"DMIN", &g.dmin_mm}, {"DMAX", &g.dmax_mm}, {"ARES", &g.ares},
                          {"AMIN", &g.amin},    {"AMAX", &g.amax},    {"AFRT", &g.afrt},
                          {"SCAN", &g.scan_rpm}};
  int seen = 0;
  for (int l = 2; l < lines.count; ++l) {
    const char *key = nullptr, *value = nullptr;
    std::size_t kl = 0, vl = 0;
    if (!parse_info(lines.text[l], lines.len[l], key, kl, value, vl))
      return why = "PP line malformed or its sum wrong", false;
    for (const Field& f : fields) {
      if (!key_is(key, kl, f.key)) continue;
      if (!read_int(value, vl, *f.dst)) return why = "PP value not a number", false;
      ++seen;
    }
  }
  if (seen < 7 || !g.complete()) return why = "PP lacks a field or is inconsistent", false;
  return true;
}

bool parse_info_reply(const Lines& lines, Command cmd, const char* key, char* value,
                      std::size_t cap, const char*& why) {
  if (!header_ok(lines, cmd, why)) return false;
  if (value != nullptr && cap > 0) value[0] = '\0';
  for (int l = 2; l < lines.count; ++l) {
    const char *k = nullptr, *v = nullptr;
    std::size_t kl = 0, vl = 0;
    if (!parse_info(lines.text[l], lines.len[l], k, kl, v, vl))
      return why = "info line malformed or its sum wrong", false;
    if (key != nullptr && value != nullptr && cap > 0 && key_is(k, kl, key)) {
      const std::size_t m = vl < cap - 1 ? vl : cap - 1;
      std::memcpy(value, v, m);
      value[m] = '\0';
    }
  }
  return true;
}

// --- Ranges ---

std::uint32_t range_to_wire(float range_m, int dmin_mm, int chars) {
  if (std::isnan(range_m)) return kCodeInvalid;
  if (std::isinf(range_m)) return std::signbit(range_m) ? kCodeTooClose : kCodeNoReturn;
  if (std::signbit(range_m) && range_m != 0.0F) return kCodeInvalid;
  if (range_m == 0.0F) return kCodeZero;
  const double mm = double(range_m) * 1000.0;
  const double top = double(max_encodable(chars));
  if (std::isgreater(mm, top)) return max_encodable(chars);
  const auto v = static_cast<std::uint32_t>(std::llround(mm));
  return v < std::uint32_t(dmin_mm) ? kCodeTooClose : v;
}

float wire_to_range(std::uint32_t v, int dmin_mm) {
  if (v == kCodeZero) return 0.0F;
  if (v == kCodeNoReturn) return std::numeric_limits<float>::infinity();
  if (v == kCodeTooClose) return -std::numeric_limits<float>::infinity();
  if (v == kCodeInvalid || v < std::uint32_t(dmin_mm))
    return std::numeric_limits<float>::quiet_NaN();
  return float(double(v) / 1000.0);
}

}  // namespace carril::hal::scip
