#include "core/atomic_file.h"

#include <unistd.h>

#include <atomic>

#include "core/error.h"

namespace pensight {

std::filesystem::path temporary_sibling(const std::filesystem::path& path) {
  static std::atomic<int> counter{0};
  // Built with append: GCC 12 warns falsely (-Wrestrict) on chained operator+ here.
  std::string name = ".";
  name.append(path.filename().string()).append(".tmp-").append(std::to_string(::getpid()));
  name.append("-").append(std::to_string(counter++));
  return path.parent_path() / name;
}

AtomicFile::AtomicFile(std::filesystem::path path)
    : path_(std::move(path)), temp_(temporary_sibling(path_)) {
  out_.open(temp_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    throw Error("cannot write '" + temp_.string() + "' (for '" + path_.string() +
                "'): check that the folder exists and is writable");
  }
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  out_.close();
  std::error_code ec;
  std::filesystem::remove(temp_, ec);
}

void AtomicFile::commit() {
  out_.flush();
  const bool ok = static_cast<bool>(out_);
  out_.close();
  if (!ok) throw Error("writing '" + path_.string() + "' failed (disk full?)");
  std::error_code ec;
  std::filesystem::rename(temp_, path_, ec);
  if (ec)
    throw Error("cannot rename '" + temp_.string() + "' to '" + path_.string() +
                "': " + ec.message());
  committed_ = true;
}

void write_file_atomically(const std::filesystem::path& path, std::string_view bytes) {
  AtomicFile file(path);
  file.stream().write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  file.commit();
}

}  // namespace pensight
