#pragma once
// The C interface of libcarril_sim_window.so, the one piece of carril_sim that needs a GUI
// toolkit (OpenCV highgui: Qt, and through it some 130 shared libraries). carril_sim loads it
// with dlopen only for --view, so a run without a window starts in 0.02 s instead of 0.2 s;
// campaigns start thousands of runs. LiveView draws the picture; this only shows it.
#include <cstddef>

extern "C" {
// Opens the window named `title`; 0 on success.
int carril_view_open(const char* title);
// Shows an 8-bit BGR image (`rows` x `cols`, `step` bytes per row) and polls the keyboard for
// about a millisecond; returns 1 while the window is open and neither q nor Esc was pressed.
int carril_view_show(const char* title, int rows, int cols, const unsigned char* bgr,
                     std::size_t step);
// Closes every window.
void carril_view_close(void);
}
