#pragma once
// A ROI's lattice corrected for its perspective chirp. A 300 px ROI spans 36 deg of view, so on an
// oblique net the lattice's frequency drifts across it: the image of the net is a chirp, and the
// FFT's strongest bin lies where the spectral density is highest (where the frequency changes
// slowest, on the nearer, coarser side), not at the lattice of the ROI's centre. Uncorrected, far
// and oblique ROIs read their range 1-2 % short at 30 deg, and psi reads 1-2 % of itself low;
// frontal ROIs read 0.1-0.25 % long (the log-parabola vertex on a Hann lobe).
//
// Method: the windowed spectrum is modelled by stationary phase, as the sum over the ROI of
// w(x)^2 H(f(x))^2 |W(k - N f(x))|^2, where f(x) is the local lattice frequency that the net
// plane gives at pixel x, w the ROI's window, W its transform, H the known transfer of pixel
// footprint and resampling (N = ROI size in pixels, k in bins). Its peaks are located with the
// detector's own rule (strongest bin, log-parabola vertex; kernels::peak_vertex), and the
// measurement is moved by the difference between that prediction and the lattice at the point's
// pixel: one fixed-point step, exact to first order in the bias. docs/fft_detection.md has the
// measurements.
//
// Cost: 16 x 16 positions (the field evaluated at 9 x 9 of them), per peak one product of
// (bins_y x 256) (256 x bins_x); about 60 us per ROI, 1.8 ms per frame of 30 ROIs on one core.
#include <Eigen/Core>

#include "core/camera.h"
#include "kernels/fft_roi/fft_roi.h"

namespace pensight {

struct ChirpModelParams {
  bool window = true;     // the ROI's Hann window (kernels::FftRoiShape::window)
  bool subbin = true;     // log-parabola refinement (kernels::PeakParams::subbin)
  bool resampled = true;  // the ROI is resampled (roi_size_px != fft_size)
  // The lattice is corrected only where its energy centroid (the point's pixel) lies within this
  // share of the ROI size of the model's own: on oblique full nets the two differ by up to 1.2 %
  // (the far side's finer twines are softer than the model has them); a ROI a third on water,
  // which still passes NetPointParams::max_centroid_share, by 4-5 %.
  double max_centroid_gap_share = 0.02;
};

// `measured`: the kernel's lattice of the ROI at `origin` (size `roi_size_px` px), assigned to
// pixel `point_px` (the ROI's centre plus its energy centroid); the net plane there has unit normal
// `normal_C` (C, any sign). Returns `measured` with f1, f2 corrected; unchanged where the
// geometry is degenerate (a ray parallel to the plane, a lattice vector that does not project),
// the chirp spreads a peak over more than 128 bins, or the centroids disagree (above). Pure
// function, no exceptions.
kernels::RoiLattice chirp_corrected(const kernels::RoiLattice& measured, kernels::RoiOrigin origin,
                                    int roi_size_px, const Eigen::Vector2d& point_px,
                                    const PinholeCamera& camera, const Eigen::Vector3d& normal_C,
                                    const ChirpModelParams& params = {});

}  // namespace pensight
