#pragma once
// Output files written whole: the bytes go to a temporary name beside the target and are renamed
// onto it only when complete, so a crash or an error never leaves a truncated file that looks
// complete.
#include <filesystem>
#include <fstream>
#include <string_view>

namespace pensight {

class AtomicFile {
 public:
  // Opens the temporary file; throws pensight::Error when the folder is not writable.
  explicit AtomicFile(std::filesystem::path path);
  // Removes the temporary file unless commit() succeeded.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return out_; }
  // The temporary file, for writers that open files by name (OpenVDB): they write it while
  // stream() stays unused; stream() then continues after seekp(0, std::ios::end).
  const std::filesystem::path& temp_path() const { return temp_; }
  // Flushes, closes and renames onto the target path (replacing it).
  void commit();

 private:
  std::filesystem::path path_;
  std::filesystem::path temp_;
  std::ofstream out_;
  bool committed_ = false;
};

// The whole of `bytes` as `path`, by AtomicFile; throws pensight::Error as it does.
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

// Name for temporary siblings of `path`: hidden, with the process id, never mistaken for it.
std::filesystem::path temporary_sibling(const std::filesystem::path& path);

}  // namespace pensight
