#include "hal/linux/StdoutConsole.hpp"

#include <unistd.h>

#include <cstring>

namespace carril::hal {

void StdoutConsole::write_line(const char* line) {
  char buf[512];
  std::size_t n = std::strlen(line);
  if (n > sizeof buf - 1) n = sizeof buf - 1;
  std::memcpy(buf, line, n);
  buf[n++] = '\n';
  // A status line lost to a full pipe is not worth blocking for; partial writes are retried.
  std::size_t done = 0;
  while (done < n) {
    const ssize_t w = ::write(STDOUT_FILENO, buf + done, n - done);
    if (w <= 0) return;
    done += static_cast<std::size_t>(w);
  }
}

}  // namespace carril::hal
