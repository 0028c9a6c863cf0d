#pragma once
// The per-user cache directory for artefacts that are expensive to recompute and safe to lose
// (Vulkan pipeline cache, FFTW wisdom): $PENSIGHT_CACHE_DIR, else $XDG_CACHE_HOME/pensight, else
// ~/.cache/pensight; empty when none is known. "-" (from PENSIGHT_CACHE_DIR) means no disk cache.
#include <filesystem>
#include <string>
#include <string_view>

namespace pensight {

std::filesystem::path cache_dir();

// Writes by write_file_atomically (core/atomic_file.h), so a concurrent reader never sees a
// truncated file; creates the directory. Failures (read-only home) are ignored: the cache is
// an optimisation.
void write_cache_file(const std::filesystem::path& path, std::string_view bytes);

}  // namespace pensight
