#pragma once
// `pensight record`: the configured live sources (record_config.h) written into a dataset in the
// shared layout as they arrive (cam0, dvl0, pressure0 from the water's barometer, imu0 from
// ATTITUDE; each log with its samples' raw device times in a last column). The dataset is
// streamed (DatasetWriter's kStreaming): a recorder that is killed leaves a readable dataset up to
// its last complete row. Faults of the devices are counted, never thrown after construction:
// while recording, each source's counters that grew are said (at most once a second per source),
// as is a source without a sample for silence_s and its return; summary() tells each source's
// rate, drops, errors and clock offset.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "live/record_config.h"

namespace pensight::live {

struct FaultCount {
  std::string name;  // e.g. "drops", "malformed"
  uint64_t count = 0;
  bool first_is_expected = false;  // "connects": the first is the connection, not a fault
  std::string reason;              // the latest one in words, where the source keeps it
};

struct SourceSummary {
  std::string name;                        // "cam0", "dvl0", "pressure0", "imu0"
  uint64_t samples = 0;                    // written
  uint64_t out_of_order = 0;               // a time stamp not after the previous one: not written
  std::vector<FaultCount> faults;          // the source's counters of drops and errors
  std::optional<int64_t> clock_offset_ns;  // host stamp - device time of the last sample
};

class Recorder {
 public:
  // Opens the sources and the dataset at `out` (absent or an empty folder). Throws
  // pensight::Error for an unusable configuration or output folder.
  Recorder(const RecordConfig& config, const std::filesystem::path& out);
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // Records until duration_s have passed (infinite: until `stop`), `stop` is set, or a dataset:
  // camera has played its last frame; then closes the dataset.
  void run(double duration_s, const std::atomic<bool>& stop);

  std::vector<SourceSummary> summary() const;
  // The summary as a few lines of text, with the recording's length.
  std::string summary_text() const;

 private:
  struct Sources;
  std::unique_ptr<Sources> sources_;
};

}  // namespace pensight::live
