#pragma once
// Hokuyo SCIP 2.0 (the protocol of the URG/UST laser scanners, e.g. a UST-10LX on TCP port
// 10940), the subset carril uses, both sides: character encodings, checksums, command and reply
// lines, distance replies (MD/MS/GD/GS/ME) and the parameter replies (VV/PP/II). Pure and
// portable: no heap, no OS calls; everything is written into or read from the caller's buffers.
//
// Wire format (one message): echo line, status line ("00P": status + sum), then for data
// replies a time stamp line and data lines of at most 64 characters each followed by their sum;
// a message ends with an empty line (two line feeds in a row).
#include <cstddef>
#include <cstdint>

namespace carril::hal::scip {

constexpr int kMaxDataLine = 64;      // data characters per line before its sum
constexpr int kMaxTagChars = 16;      // "string characters" a command may carry after ';'
constexpr std::size_t kMaxLine = 96;  // longest line carril reads or writes, LF excluded

// --- Character encodings (6 bits per character, offset 0x30) ---

// Largest value that `chars` characters (1 to 4) hold: 2^(6 chars) - 1.
constexpr std::uint32_t max_encodable(int chars) {
  return (std::uint32_t{1} << (6 * chars)) - 1;
}
// Writes value in `chars` characters (2, 3 or 4, most significant first) to out, no terminator.
// False (out untouched) when the value does not fit or chars is out of 1..4.
bool encode(std::uint32_t value, int chars, char* out);
// Reads `chars` characters; false when one is outside '0'..'o' (0x30..0x6F).
bool decode(const char* in, int chars, std::uint32_t& value);

// The SCIP sum of n bytes: the low 6 bits of their byte sum, plus 0x30.
char checksum(const char* s, std::size_t n);

// --- Lines ---

// The line's data (all but the last character) has the sum in its last character.
bool line_sum_ok(const char* line, std::size_t n);
// A status line "SSs": two status characters and their sum. Writes the two characters to
// status[0..1]; false when the length or the sum is wrong.
bool parse_status(const char* line, std::size_t n, char status[2]);

// SCIP status codes carril uses (two ASCII characters).
constexpr char kStatusOk[] = "00";              // command accepted
constexpr char kStatusData[] = "99";            // a scan of a running MD/MS/ME
constexpr char kStatusLaserOn[] = "02";         // BM: laser was already on
constexpr char kStatusLaserOff[] = "10";        // GD/GS: laser is off (send BM first)
constexpr char kStatusBadStart[] = "01";        // MD/GD: start step not numeric
constexpr char kStatusBadEnd[] = "02";          // MD/GD: end step not numeric
constexpr char kStatusBadCluster[] = "03";      // MD/GD: cluster count not numeric
constexpr char kStatusEndRange[] = "04";        // MD/GD: end step beyond AMAX
constexpr char kStatusEndBeforeStart[] = "05";  // MD/GD: end step before start step
constexpr char kStatusBadInterval[] = "06";     // MD: scan interval not numeric
constexpr char kStatusBadScans[] = "07";        // MD: number of scans not numeric
constexpr char kStatusUnknown[] = "0E";         // command not understood

// --- Commands (host to sensor) ---

enum class Command : std::uint8_t { Unknown, MD, MS, GD, GS, ME, VV, PP, II, BM, QT, RS };

// A command line as the sensor reads it. Steps and counts only for the data commands.
struct Request {
  Command cmd = Command::Unknown;
  char code[2] = {};                // the two command letters as received
  int start_step = 0;               // first step [steps]
  int end_step = 0;                 // last step [steps]
  int cluster = 1;                  // steps merged into one value (0 and 1 both mean 1)
  int interval = 0;                 // MD/MS/ME: scans skipped between two sent
  int scans = 0;                    // MD/MS/ME: scans to send, 0 = until QT
  char tag[kMaxTagChars + 1] = {};  // string characters after ';' (without it)
  // Status to answer with: "00" when well formed, else the SCIP error of the first bad field.
  char status[2] = {'0', '0'};
};
// Parses one command line (LF or CR excluded). Never fails: a malformed line gives a Request
// whose status names the first bad field (kStatusUnknown for an unknown command).
Request parse_request(const char* line, std::size_t n);
// Writes a data command ("MD0000108001000\n") to out (capacity cap), returning its length with
// the LF, or 0 when it does not fit or a field is out of range. scans: 0 = continuous.
std::size_t format_data_request(Command cmd, int start_step, int end_step, int cluster,
                                int interval, int scans, char* out, std::size_t cap);
// Writes a two-letter command (VV, PP, II, BM, QT, RS) with its LF; returns 3 (0 if cap < 3).
std::size_t format_simple_request(Command cmd, char* out, std::size_t cap);

// --- Replies (sensor to host) ---

// Appends reply text to a caller's buffer; every method returns false once it has run out of
// room (the buffer then holds a cut message that must not be sent).
class ReplyWriter {
 public:
  ReplyWriter(char* buf, std::size_t cap) : buf_(buf), cap_(cap) {}
  // The echo of a request: its letters, its fields as received, and ";tag" when it had one.
  // For MD/MS/ME scans, `remaining` replaces the number of scans (-1: echo as requested).
  bool echo(const Request& r, int remaining = -1);
  bool raw_line(const char* text, std::size_t n);  // text + LF, no sum
  bool status(const char code[2]);                 // "SS" + sum + LF
  bool info(const char* key, const char* value);   // "KEY:value;" + sum of "KEY:value" + LF
  bool timestamp(std::uint32_t ms);                // 4-character time stamp + sum + LF
  // Values of `chars` characters each (1 to 4; any other fails the writer), split into lines of
  // 64 with their sums.
  bool data(const std::uint32_t* values, int count, int chars);
  bool end();  // the empty line that ends a message
  std::size_t size() const { return ok_ ? len_ : 0; }
  bool ok() const { return ok_; }

 private:
  bool put(const char* s, std::size_t n);
  char* buf_;
  std::size_t cap_;
  std::size_t len_ = 0;
  bool ok_ = true;
};

// A message split into its lines: in points into the caller's text (one whole message, up to
// and including its final empty line).
struct Lines {
  static constexpr int kMax = 200;  // ME: 2048 beams * 6 chars / 64 = 192 data lines, + 3
  const char* text[kMax] = {};
  std::size_t len[kMax] = {};
  int count = 0;  // lines before the empty one
};
// Splits one message; false when it has more than Lines::kMax lines or does not end with an
// empty line.
bool split_lines(const char* msg, std::size_t n, Lines& out);

enum class ReplyError : std::uint8_t {
  None,
  Truncated,    // fewer lines or characters than the echo asks for
  BadChecksum,  // a line's sum does not match
  BadEcho,      // echo line not a data command, or not the expected one
  BadStatus,    // status is an error code (see Distances::status)
  BadEncoding,  // a character outside the encoding's alphabet
  TooLong,      // more values than the caller's buffer holds
};
// Lower-case words for a ReplyError, static storage.
const char* reply_error_text(ReplyError e);

// A decoded MD/MS/GD/GS/ME message.
struct Distances {
  Request echo;                // the echo line parsed as a request
  char status[2] = {};         // "00" (MD acknowledgement, no data), "99" (scan) or an error
  bool has_data = false;       // false: an acknowledgement or error without a scan
  std::uint32_t stamp_ms = 0;  // sensor time stamp [ms], 24 bits, wraps
  int count = 0;               // values decoded (intensities not counted)
};
// Decodes one distance message (lines from split_lines). Ranges go to ranges[0..cap) [mm or
// error code], intensities (ME only, may be null) to intensities[]. Checks every sum and that
// the data length is what the echo's steps and cluster ask for.
ReplyError parse_distances(const Lines& lines, std::uint32_t* ranges, std::uint32_t* intensities,
                           int cap, Distances& out);

// --- Parameters (PP) ---

// Scan geometry as PP reports it. Step s points at (s - afrt) * 2 pi / ares [rad], counter-
// clockwise, 0 = the sensor's front.
struct Geometry {
  int dmin_mm = 0;        // DMIN: shortest valid distance [mm]
  int dmax_mm = 0;        // DMAX: longest valid distance [mm]
  int ares = 0;           // ARES: steps in a full turn
  int amin = 0;           // AMIN: first measured step
  int amax = 0;           // AMAX: last measured step
  int afrt = 0;           // AFRT: the step straight ahead
  int scan_rpm = 0;       // SCAN: motor speed [rpm]
  bool complete() const;  // every field seen and consistent (dmin < dmax, amin <= afrt...)
};
// One "KEY:value;s" line: checks the sum (of "KEY:value") and splits it. key/value point into
// line; false when there is no ':' or ';' or the sum is wrong.
bool parse_info(const char* line, std::size_t n, const char*& key, std::size_t& key_len,
                const char*& value, std::size_t& value_len);
// Reads a whole PP message (echo "PP", status "00", info lines) into g. Unknown keys are
// skipped (MODL); false with a reason in why (static text) when a line is bad or a field is
// missing.
bool parse_pp(const Lines& lines, Geometry& g, const char*& why);
// Checks a VV or II message: echo cmd, status "00", every info line's sum. Copies the value of
// `key` (e.g. "PROD", "MODL"; may be null) into value (cap chars with terminator).
bool parse_info_reply(const Lines& lines, Command cmd, const char* key, char* value,
                      std::size_t cap, const char*& why);

// --- Ranges: metres (REP 117) <-> millimetres and SCIP error codes ---
//
// Hokuyo sensors report values below DMIN as error codes. carril's server uses three of them so
// that REP 117's three special values survive the wire; the client maps any other code to NaN:
//   0 -> 0 m (an invalid 0, passed through as drivers do), 1 -> +inf (no return within range),
//   2 -> -inf (closer than range_min), 3..DMIN-1 -> NaN (invalid measurement).
// Values from DMIN up are millimetres, those beyond DMAX included (out-of-limit, passed through
// so the firmware's limit checks see them).
constexpr std::uint32_t kCodeZero = 0;
constexpr std::uint32_t kCodeNoReturn = 1;
constexpr std::uint32_t kCodeTooClose = 2;
constexpr std::uint32_t kCodeInvalid = 3;

// Range [m] to its wire value (chars = 2 or 3 decides the largest millimetre value sent).
std::uint32_t range_to_wire(float range_m, int dmin_mm, int chars);
// Wire value to range [m].
float wire_to_range(std::uint32_t v, int dmin_mm);

}  // namespace carril::hal::scip
