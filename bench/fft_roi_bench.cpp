// FFT net detection for the default grid (30 ROIs of 300 px from 720x540 u8, resampled to 256^2),
// side by side in one run:
//  - the whole stage (resample + normalise + window + FFT + peak search): CPU reference on FFTW
//    with 1 and 2 threads, and Vulkan (upload, one submission, download of 30 x 24 bytes);
//  - the stage plus net geometry and relative pose (the CPU budget: <= 10 ms per frame);
//  - the spectra alone on the same windowed samples: FFTW plan_many (the peer), OpenCV cv::dft,
//    our FFTW-per-ROI path, our Vulkan radix-2 shaders;
//  - the CPU stage's pieces: prepare (resample + normalise + window), peaks, net points + pose.
// "cpu_ms" is the process CPU time per iteration over all threads (getrusage), the cost on a
// shared machine; the CPU column of Google Benchmark counts the main thread only.
// Floor: 30 real 256^2 FFTs = 30 * 5 N log2 N / 2 flops with N = 256^2 points (the complex count
// halved for real input) = 78.6 MFlop; "x_fftw" is each spectra time over FFTW plan_many's in this
// run.
#include <benchmark/benchmark.h>
#include <fftw3.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <vector>

#include "core/timing.h"
#include "kernels/fft_roi/fft_roi.h"
#include "pipeline/fft/fine_mesh_probe.h"
#include "pipeline/fft/grid_plan.h"
#include "pipeline/fft/net_detector.h"
#include "runtime/vk_buffer.h"
#include "runtime/vk_context.h"
#include "runtime/vk_stream.h"

namespace {

using namespace pensight;

constexpr int kN = 256;
constexpr size_t kNN = static_cast<size_t>(kN) * kN;
constexpr size_t kNC = static_cast<size_t>(kN) * (kN / 2 + 1);

// A net-like frame: twine lattice with perspective-free period, slight rotation, noise; the
// twine is 3 / 22 of the period.
ImageU8 frame_of(int width, int height, double period_px) {
  ImageU8 img(width, height);
  uint32_t state = 1;
  const double twine_px = 3.0 / 22.0 * period_px;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double u = 0.996 * x + 0.087 * y, v = -0.087 * x + 0.996 * y;
      const bool twine = std::fmod(u, period_px) < twine_px || std::fmod(v, period_px) < twine_px;
      state = state * 1664525u + 1013904223u;
      img.at(x, y) = static_cast<uint8_t>((twine ? 180 : 70) + (state >> 28));
    }
  }
  return img;
}

ImageU8 frame() {
  return frame_of(720, 540, 22.0);
}

const std::vector<kernels::RoiOrigin>& grid() {
  static const auto rois = kernels::roi_grid(720, 540, {});
  return rois;
}

// The windowed samples every spectra benchmark transforms.
const std::vector<float>& samples() {
  static const std::vector<float> s = [] {
    kernels::FftRoiCpu cpu({}, {}, 1, kernels::FftPlanning::kQuick);
    std::vector<float> out(grid().size() * kNN);
    cpu.prepare(frame(), grid(), out);
    return out;
  }();
  return s;
}

double flops() {
  return 30.0 * 5.0 * static_cast<double>(kNN) * std::log2(double(kNN)) / 2;
}

struct FftwMany {
  float* in;
  fftwf_complex* out;
  fftwf_plan plan;
  explicit FftwMany(unsigned flags) {
    in = fftwf_alloc_real(grid().size() * kNN);
    out = fftwf_alloc_complex(grid().size() * kNC);
    const int n[2] = {kN, kN};
    plan = fftwf_plan_many_dft_r2c(2, n, static_cast<int>(grid().size()), in, nullptr, 1,
                                   static_cast<int>(kNN), out, nullptr, 1, static_cast<int>(kNC),
                                   flags);
    std::copy(samples().begin(), samples().end(), in);
  }
  ~FftwMany() {
    fftwf_destroy_plan(plan);
    fftwf_free(in);
    fftwf_free(out);
  }
};

// FFTW plan_many time for this run (FFTW_PATIENT, as FftRoiCpu plans), measured once (median of
// 31), for the x_fftw ratios.
double fftw_ms() {
  static const double ms = [] {
    FftwMany f(FFTW_PATIENT);
    std::vector<double> t;
    for (int i = 0; i < 31; ++i) {
      Stopwatch sw;
      fftwf_execute(f.plan);
      t.push_back(sw.elapsed_ms());
    }
    std::nth_element(t.begin(), t.begin() + 15, t.end());
    return t[15];
  }();
  return ms;
}

// Process CPU time (all threads, user + system), ms.
double process_cpu_ms() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  const auto ms = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_usec) / 1e3;
  };
  return ms(u.ru_utime) + ms(u.ru_stime);
}

void spectra_counters(benchmark::State& state, double total_ms) {
  const double ms = total_ms / static_cast<double>(state.iterations());
  state.counters["MFlop"] = flops() / 1e6;
  state.counters["GFlop/s"] = flops() / (ms * 1e6);
  state.counters["x_fftw"] = ms / fftw_ms();
}

// Arg 0: FFTW_MEASURE; 1: FFTW_PATIENT (~15 s of planning, once per process).
void BM_Spectra_FftwPlanMany(benchmark::State& state) {
  FftwMany f(state.range(0) ? FFTW_PATIENT : FFTW_MEASURE);
  Stopwatch sw;
  for (auto _ : state) {
    fftwf_execute(f.plan);
    benchmark::DoNotOptimize(f.out);
  }
  spectra_counters(state, sw.elapsed_ms());
}
BENCHMARK(BM_Spectra_FftwPlanMany)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Spectra_CvDft(benchmark::State& state) {
  cv::setNumThreads(1);
  std::vector<cv::Mat> in, out(grid().size());
  for (size_t r = 0; r < grid().size(); ++r) {
    in.emplace_back(kN, kN, CV_32F, const_cast<float*>(samples().data() + r * kNN));
  }
  Stopwatch sw;
  for (auto _ : state) {
    for (size_t r = 0; r < in.size(); ++r) cv::dft(in[r], out[r]);  // packed CCS real spectrum
    benchmark::DoNotOptimize(out[0].data);
  }
  spectra_counters(state, sw.elapsed_ms());
}
BENCHMARK(BM_Spectra_CvDft)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Spectra_FftRoiCpu(benchmark::State& state) {
  kernels::FftRoiCpu cpu({}, {}, static_cast<int>(state.range(0)));
  std::vector<std::complex<float>> out(grid().size() * kNC);
  Stopwatch sw;
  for (auto _ : state) {
    cpu.transform(samples(), out);
    benchmark::DoNotOptimize(out.data());
  }
  spectra_counters(state, sw.elapsed_ms());
}
BENCHMARK(BM_Spectra_FftRoiCpu)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Spectra_Vulkan(benchmark::State& state) {
  const vk::Context ctx;
  state.SetLabel(ctx.info().name);
  const kernels::FftRoiVk kernel(ctx, {});
  const auto n = static_cast<uint32_t>(grid().size());
  vk::Buffer in(ctx, kernel.samples_bytes(n)), out(ctx, kernel.spectrum_bytes(n));
  in.upload(samples().data(), kernel.samples_bytes(n));
  vk::CommandStream stream(ctx);
  kernel.record_fft(stream, in, out, n);
  double device_ms = 0;
  Stopwatch sw;
  for (auto _ : state) {
    stream.submit_and_wait();
    for (const auto& t : stream.timings()) device_ms += t.device_ms;
  }
  spectra_counters(state, sw.elapsed_ms());
  state.counters["device_ms"] = device_ms / static_cast<double>(state.iterations());
}
BENCHMARK(BM_Spectra_Vulkan)->Unit(benchmark::kMillisecond)->UseRealTime();

// The stage's pieces on the CPU: resample + normalise + window alone.
void BM_Prepare_Cpu(benchmark::State& state) {
  kernels::FftRoiCpu cpu({}, {}, static_cast<int>(state.range(0)), kernels::FftPlanning::kQuick);
  const ImageU8 img = frame();
  std::vector<float> out(grid().size() * kNN);
  const double cpu0 = process_cpu_ms();
  for (auto _ : state) {
    cpu.prepare(img, grid(), out);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["cpu_ms"] = (process_cpu_ms() - cpu0) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_Prepare_Cpu)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Peak search alone on the 30 spectra of the same frame.
void BM_Peaks_Cpu(benchmark::State& state) {
  kernels::FftRoiCpu cpu({}, {}, 1);
  std::vector<std::complex<float>> spectra(grid().size() * kNC);
  cpu.transform(samples(), spectra);
  for (auto _ : state) {
    for (size_t r = 0; r < grid().size(); ++r) {
      benchmark::DoNotOptimize(kernels::analyze_spectrum(
          std::span<const std::complex<float>>(spectra).subspan(r * kNC, kNC), {}, {}));
    }
  }
}
BENCHMARK(BM_Peaks_Cpu)->Unit(benchmark::kMillisecond)->UseRealTime();

// Net points + relative pose alone, from the frame's 30 lattices.
void BM_Pose_Cpu(benchmark::State& state) {
  kernels::FftRoiCpu cpu({}, {}, 1);
  const auto lattices = cpu.run(frame(), grid());
  const PinholeCamera camera;
  for (auto _ : state) {
    std::vector<RoiNetPoint> points;
    for (size_t i = 0; i < grid().size(); ++i) {
      points.push_back(roi_net_point(lattices[i], grid()[i], 300, camera, {0.030}));
    }
    benchmark::DoNotOptimize(relative_pose_fft(points));
  }
}
BENCHMARK(BM_Pose_Cpu)->Unit(benchmark::kMillisecond)->UseRealTime();

// Net texture odometry per frame: the 256 px patch about the image centre and the step from the
// previous one (two Fourier coefficients of each patch). Floor: 4 x 256^2 complex multiply-adds
// (~1.6 Mflop) plus windowing 256^2 pixels, ~0.2 ms on one core at ~10 Gflop/s.
void BM_NetTexture_Cpu(benchmark::State& state) {
  kernels::FftRoiCpu cpu({}, {}, 1);
  const ImageU8 img = frame();
  const auto lattices = cpu.run(img, grid());
  const PinholeCamera camera;
  std::vector<RoiNetPoint> points;
  for (size_t i = 0; i < grid().size(); ++i)
    points.push_back(roi_net_point(lattices[i], grid()[i], 300, camera, {0.030}));
  const FftRelativePose pose = relative_pose_fft(points);
  const NetTextureParams params;
  const TexturePatch previous = texture_patch(img, camera, 0, params);
  for (auto _ : state) {
    const TexturePatch patch = texture_patch(img, camera, 1, params);
    benchmark::DoNotOptimize(texture_step(previous, patch, points, pose, camera, 0.030, params));
  }
  state.counters["valid"] =
      texture_step(previous, previous, points, pose, camera, 0.030, params).valid;
}
BENCHMARK(BM_NetTexture_Cpu)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_FftStage_Cpu(benchmark::State& state) {
  kernels::FftRoiCpu cpu({}, {}, static_cast<int>(state.range(0)));
  const ImageU8 img = frame();
  const double cpu0 = process_cpu_ms();
  for (auto _ : state) benchmark::DoNotOptimize(cpu.run(img, grid()));
  state.counters["cpu_ms"] = (process_cpu_ms() - cpu0) / static_cast<double>(state.iterations());
  state.counters["rois"] = static_cast<double>(grid().size());
}
BENCHMARK(BM_FftStage_Cpu)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Whole stage on the Vulkan device: upload the frame, one submission of the four dispatches,
// download the 30 lattices. device_ms: sum of the dispatches' device times.
void BM_FftStage_Vulkan(benchmark::State& state) {
  const vk::Context ctx;
  state.SetLabel(ctx.info().name);
  const kernels::FftRoiVk kernel(ctx, {});
  const ImageU8 img = frame();
  const auto n = static_cast<uint32_t>(grid().size());
  vk::Buffer image(ctx, kernel.image_bytes()), rois(ctx, n * sizeof(kernels::RoiOrigin));
  rois.upload(grid().data(), n * sizeof(kernels::RoiOrigin));
  vk::Buffer samp(ctx, kernel.samples_bytes(n)), spec(ctx, kernel.spectrum_bytes(n));
  vk::TypedBuffer<kernels::RoiLattice> lat(ctx, n, vk::MemoryUsage::kReadback);
  vk::CommandStream stream(ctx);
  kernel.record(stream, image, rois, samp, spec, lat.raw(), n);
  double device_ms = 0;
  std::vector<double> per(4, 0.0);
  for (auto _ : state) {
    image.upload(img.pixels.data(), img.pixels.size());
    stream.submit_and_wait();
    benchmark::DoNotOptimize(lat.to_vector());
    const auto t = stream.timings();
    for (size_t i = 0; i < t.size() && i < per.size(); ++i) per[i] += t[i].device_ms;
    for (const auto& d : t) device_ms += d.device_ms;
  }
  const auto iters = static_cast<double>(state.iterations());
  state.counters["device_ms"] = device_ms / iters;
  const char* names[] = {"extract_ms", "rows_ms", "cols_ms", "peaks_ms"};
  for (size_t i = 0; i < per.size(); ++i) state.counters[names[i]] = per[i] / iters;
}
BENCHMARK(BM_FftStage_Vulkan)->Unit(benchmark::kMillisecond)->UseRealTime();

// The detector on `img` once per iteration; the FFT and pose parts' mean times as counters.
void detect_every_iteration(benchmark::State& state, NetDetector& detector, const ImageU8& img) {
  double fft = 0, pose = 0;
  for (auto _ : state) {
    const NetDetection d = detector.detect(img);
    fft += d.fft_ms;
    pose += d.pose_ms;
    if (!d.pose.valid()) state.SkipWithError(d.pose.reason.c_str());
  }
  const auto iters = static_cast<double>(state.iterations());
  state.counters["fft_ms"] = fft / iters;
  state.counters["pose_ms"] = pose / iters;
}

// The CPU budget: FFT stage + per-ROI geometry + relative pose, per 720x540 frame.
void BM_FftStagePlusPose_Cpu(benchmark::State& state) {
  Device device;
  NetDetector detector(PinholeCamera{},
                       {.backend = Backend::kCpu, .cpu_threads = static_cast<int>(state.range(0))},
                       device);
  const double cpu0 = process_cpu_ms();
  detect_every_iteration(state, detector, frame());
  state.counters["cpu_ms"] = (process_cpu_ms() - cpu0) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_FftStagePlusPose_Cpu)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Any camera (grid_plan.h): the same net through the reference field of view on larger frames
// (fx and the lattice period scaled with the width), the ROI side and FFT size planned, 1 thread.
// Args: width, height. The FFT's work is the reference's (30 ROIs of 256^2); resampling reads
// each ROI's pixels, (800 / 300)^2 = 7.1x the reference's at 1920x1080, 28x at 3840x2160.
void BM_FftStagePlusPose_FrameSize(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0)), height = static_cast<int>(state.range(1));
  Device device;
  NetDetector detector(default_field_of_view(width, height),
                       {.backend = Backend::kCpu, .cpu_threads = 1}, device);
  detect_every_iteration(state, detector, frame_of(width, height, 22.0 * width / 720.0));
  state.counters["roi_px"] = detector.config().grid.roi_size_px;
}
BENCHMARK(BM_FftStagePlusPose_FrameSize)
    ->Args({720, 540})
    ->Args({1920, 1080})
    ->Args({3840, 2160})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The grid's choice (issue 45: under 1 ms whenever it is made): the plan from the camera, and the
// fine-mesh probe's look at the frame's centre (one 256^2 FFT, every resampled frame), which
// sends the frame to the planned or the native grid. Args: width, height.
void BM_GridChoice(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0)), height = static_cast<int>(state.range(1));
  const PinholeCamera camera = default_field_of_view(width, height);
  const NetDetectorConfig given{.backend = Backend::kCpu, .cpu_threads = 1};
  const NetDetectorConfig planned = planned_detector_config(given, camera);
  FineMeshProbe probe({.width = width,
                       .height = height,
                       .roi_size_px = planned.grid.roi_size_px,
                       .fft_size = planned.fft_size},
                      planned.peaks, planned.points.min_quality);
  const ImageU8 img = frame_of(width, height, 22.0 * width / 720.0);
  Stopwatch sw;
  double plan_ms = 0;
  for (auto _ : state) {
    sw.restart();
    benchmark::DoNotOptimize(planned_detector_config(given, camera).grid.roi_size_px);
    plan_ms += sw.elapsed_ms();
    benchmark::DoNotOptimize(probe.too_fine(img));
  }
  state.counters["plan_ms"] = plan_ms / static_cast<double>(state.iterations());
  state.counters["roi_px"] = planned.grid.roi_size_px;
}
BENCHMARK(BM_GridChoice)
    ->Args({720, 540})
    ->Args({1920, 1080})
    ->Args({3840, 2160})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
