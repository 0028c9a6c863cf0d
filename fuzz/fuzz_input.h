#pragma once
// What every fuzz target shares. The readers under test take files, as the pipeline calls them,
// so an input is written to a file in a per-process folder first. pensight::Error is a reader's
// answer to a malformed input; any other exception escapes to libFuzzer, which reports it as a
// crash, as it does for a sanitizer finding.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "core/error.h"

namespace pensight::fuzz {

// A folder of this process's own under $TMPDIR (or /tmp), created on first use, emptied at exit.
const std::filesystem::path& work_dir();

// Writes data[0, size) to work_dir() / name (replacing it) and returns the path.
std::filesystem::path write_input(const uint8_t* data, size_t size, const std::string& name);

// Silences pensight's log (a reader's notes and warnings for every input would flood the run).
void quiet_log();

// Runs `read`; a pensight::Error is the expected outcome of a malformed input.
template <class Read>
void expect_clean_error(Read read) {
  try {
    read();
  } catch (const Error&) {
  }
}

}  // namespace pensight::fuzz
