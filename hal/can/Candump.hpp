#pragma once
// can-utils' candump log format, one frame a line, as `candump -l` writes it and canplayer and
// log2asc read it:  "(1436509052.249713) vcan0 44C#44A1"  (standard id: 3 hex digits; extended:
// 8; remote request: "123#R" or "123#R4" with its length; error frame: the id with bit 29 set,
// SocketCAN's CAN_ERR_FLAG). Formatting writes into a caller's buffer: no heap.
#include <cstddef>

#include "hal/CanBus.hpp"
#include "hal/Types.hpp"

namespace carril::hal {

// The longest line format_candump() writes, without its newline, for an interface name of up to
// 15 characters (IFNAMSIZ - 1).
constexpr std::size_t kCandumpMaxLine = 64;

// Writes the line for `f` received or sent at `t_ns` [ns since the epoch] on `iface` into buf
// (NUL-terminated, no newline); returns its length, or 0 when n is too small.
std::size_t format_candump(const CanFrame& f, TimeNs t_ns, const char* iface, char* buf,
                           std::size_t n);

// Reads one line back (the interface name is skipped). False, with `f` untouched, for a line
// that is not a classic CAN frame in that format, or whose time is beyond TimeNs (year 2262).
bool parse_candump(const char* line, CanFrame& f, TimeNs& t_ns);

}  // namespace carril::hal
