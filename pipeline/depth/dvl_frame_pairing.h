#pragma once
// DVL samples waiting for a camera frame, as the DVL's corrections of dense depth pair them
// (dvl_depth_scale.h, dvl_net_tilt.h): each sample meets the first frame at or after it, at most
// max_pair_dt_s later, and is used once. Samples and frames both come in timestamp order.
#include <cstdint>
#include <vector>

#include "core/dataset_types.h"

namespace pensight {

class DvlFramePairing {
 public:
  explicit DvlFramePairing(double max_pair_dt_s) : max_pair_dt_s_(max_pair_dt_s) {}

  // Pending samples more than max_pair_dt_s older than `s` are dropped: no frame can pair them
  // any more, so without frames (open water, a stage failing) the list stays this short.
  void add(const DvlSample& s);

  struct Paired {
    DvlSample sample;
    double dt_s;  // from the sample to the frame, in [0, max_pair_dt_s]
  };
  // The pending samples at most max_pair_dt_s before t_frame_ns; those and older ones leave the
  // list, later ones stay for the next frame.
  std::vector<Paired> take(int64_t t_frame_ns);

 private:
  double max_pair_dt_s_;
  std::vector<DvlSample> pending_;
};

}  // namespace pensight
