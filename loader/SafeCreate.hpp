#pragma once
// Creating output and temporary files so that nobody else's file is touched: never through a
// symlink planted at the name, never an existing file reused, and the mode the user's umask
// asks for (0666 less the umask, applied by the kernel). Shared by the atomic writer, the CAN
// logs and every other output carril writes.
#include <cstdio>
#include <string>

namespace carril::loader {

// Opens `path` for writing as a new file (O_CREAT | O_EXCL | O_NOFOLLOW): the descriptor, or -1
// with `error` = "<path>: <why>" (an existing file or symlink there is refused, not followed).
int create_exclusive(const std::string& path, std::string& error);

// A fresh temporary in the directory of `target` (".<name>.tmp.<random>"), created as
// create_exclusive() does; its name in `tmp_path`. -1 with `error` when none could be made.
int create_temp_beside(const std::string& target, std::string& tmp_path, std::string& error);

// Makes room for `path` as a new file: removes a leftover regular file of ours there (a
// FILE.part of a run that was killed), refuses anything else (a symlink, another user's file,
// a directory). True when `path` is now free; else `error` says what is in the way.
bool clear_stale_output(const std::string& path, std::string& error);

// An output stream at `path`, created new after clear_stale_output(); null with `error` set.
std::FILE* open_new_output(const std::string& path, std::string& error);

}  // namespace carril::loader
