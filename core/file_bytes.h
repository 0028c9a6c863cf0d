#pragma once
// Whole-file reads: every reader of a file that is taken in at once (PNG, ONNX, map.vdb, caches)
// reads it here. Cost: one read of the file's size into one string; no size limit of its own,
// so readers of outside data check the size they are about to trust (png_io, map_io).
#include <filesystem>
#include <optional>
#include <string>

namespace pensight {

// The file's bytes, or nullopt when it cannot be opened or read to its end (missing, a folder,
// no permission). Never throws for I/O; the caller words the error for its file.
std::optional<std::string> read_file_bytes(const std::filesystem::path& path);

}  // namespace pensight
