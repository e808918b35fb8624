#pragma once
// Where the firmware's slow rate group writes its status lines (never the control loop: writing
// is an OS call on a real target).
namespace carril::hal {

class Console {
 public:
  virtual ~Console() = default;
  // Writes one line of text (without its newline).
  virtual void write_line(const char* line) = 0;
};

}  // namespace carril::hal
