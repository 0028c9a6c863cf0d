// The CSV files of a dataset as read_dataset reads them: the camera list, the DVL, pressure and
// attitude logs and the ground truth. A valid one-frame dataset is written once; the first byte of
// an input picks the file it replaces.
#include <array>
#include <filesystem>

#include "fuzz/fuzz_input.h"
#include "pipeline/dataset/dataset_reader.h"
#include "pipeline/dataset/dataset_writer.h"

namespace {

const std::filesystem::path& dataset_root() {
  static const std::filesystem::path root = [] {
    const std::filesystem::path r = pensight::fuzz::work_dir() / "seq";
    pensight::DatasetContents c;
    c.cam0.camera.width_px = 8;
    c.cam0.camera.height_px = 6;
    c.dvl0 = pensight::DvlCalibration{};
    pensight::DatasetWriter w(r, c);
    w.add_frame(100, pensight::ImageU8(8, 6));
    w.finish();
    return r;
  }();
  return root;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  pensight::fuzz::quiet_log();
  static constexpr std::array<const char*, 5> kFiles = {"cam0/data.csv", "dvl0/data.csv",
                                                        "pressure0/data.csv", "imu0/attitude.csv",
                                                        "groundtruth0/data.csv"};
  const std::filesystem::path& root = dataset_root();
  const std::filesystem::path file = root / kFiles[data[0] % kFiles.size()];
  const std::filesystem::path saved = root / "saved.csv";
  std::filesystem::copy_file(file, saved, std::filesystem::copy_options::overwrite_existing);
  pensight::fuzz::write_input(data + 1, size - 1,
                              std::filesystem::relative(file, pensight::fuzz::work_dir()));
  pensight::fuzz::expect_clean_error([&] { pensight::read_dataset(root); });
  std::filesystem::rename(saved, file);
  return 0;
}
