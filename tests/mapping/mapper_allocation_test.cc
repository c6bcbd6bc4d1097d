// The mapper allocates nothing per frame once it has seen frames of the sizes it gets (DESIGN.md:
// hot loops allocate nothing). Every heap allocation of the process (malloc and its relatives,
// which operator new and Eigen use) is counted by interposing glibc's allocator in this executable.
#include <execinfo.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstddef>
#include <vector>

#include <gtest/gtest.h>

#include "mapping/fsgp_bgk_mapper.h"
#include "tests/mapping/mapping_test_util.h"

namespace {

// Allocations made while counting is on (the tests are single-threaded).
long allocations = 0;
bool counting = false;

void Count() {
  if (counting) {
    ++allocations;
    counting = false;
    void* frames[20];
    const int n = backtrace(frames, 20);
    backtrace_symbols_fd(frames, n, 2);
    write(2, "----\n", 5);
    counting = true;
  }
}

}  // namespace

extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* pointer, std::size_t size);
void* __libc_memalign(std::size_t alignment, std::size_t size);

void* malloc(std::size_t size) noexcept {
  Count();
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) noexcept {
  Count();
  return __libc_calloc(count, size);
}
void* realloc(void* pointer, std::size_t size) noexcept {
  Count();
  return __libc_realloc(pointer, size);
}
void* memalign(std::size_t alignment, std::size_t size) noexcept {
  Count();
  return __libc_memalign(alignment, size);
}
void* aligned_alloc(std::size_t alignment, std::size_t size) noexcept {
  Count();
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** pointer, std::size_t alignment, std::size_t size) noexcept {
  Count();
  *pointer = __libc_memalign(alignment, size);
  return *pointer != nullptr ? 0 : ENOMEM;
}
}

namespace trav::mapping {
namespace {

using testing::RobotAt;
using testing::Surface;

// Heap allocations made by `run`.
template <typename Run>
long AllocationsOf(Run run) {
  allocations = 0;
  counting = true;
  run();
  counting = false;
  return allocations;
}

// A drive along x over hummocks with a step and a wall: frames of 10 m around each position, with
// features (the step's edge), cropped points (the wall above its foot) and obstacle cells.
struct Drive {
  std::vector<common::PointCloud> frames;
  std::vector<Eigen::Isometry3d> poses;
};

Drive MakeDrive() {
  Drive drive;
  auto height = [](double x, double y) {
    return 0.15 * std::sin(x) * std::cos(0.7 * y) + (x > 3.0 && x < 3.6 ? 0.2 : 0.0);
  };
  for (int k = 0; k < 6; ++k) {
    const double x = 0.6 * k;
    common::PointCloud frame = Surface(height, {x, 0.0}, 5.0 - 0.2 * k);
    const Eigen::Index floor_points = frame.points.cols();
    frame.points.conservativeResize(3, floor_points + 40);
    for (int j = 0; j < 40; ++j) {
      frame.points.col(floor_points + j) =
          Eigen::Vector3f(6.0f, -1.0f + 0.1f * static_cast<float>(j % 20),
                          0.3f * static_cast<float>(j / 20) + 0.1f);
    }
    drive.frames.push_back(frame);
    drive.poses.push_back(RobotAt(x, 0.0));
  }
  return drive;
}

void ExpectNoAllocationOnceWarm(const FsgpConfig& config) {
  const Drive drive = MakeDrive();
  FsgpBgkMapper dut(config);
  const std::size_t n = drive.frames.size();
  double t_s = 0.0;
  // warm-up: the drive forwards and backwards, twice (the random sampling differs each time, and
  // with it the sizes of the training set's structures; FSGP-Accumulation sees the combinations of
  // frames that the measured pass repeats)
  for (std::size_t i = 0; i < 4 * n; ++i) {
    const std::size_t k = (i / n) % 2 == 0 ? i % n : n - 1 - i % n;
    ASSERT_EQ(dut.Update(drive.frames[k], drive.poses[k], t_s += 0.1).status,
              MapUpdateStatus::kUpdated);
  }
  // the drive once more
  for (std::size_t k = 0; k < n; ++k) {
    MapUpdateResult result;
    const long made =
        AllocationsOf([&] { result = dut.Update(drive.frames[k], drive.poses[k], t_s += 0.1); });
    ASSERT_EQ(result.status, MapUpdateStatus::kUpdated);
    EXPECT_GT(result.training_points, 100);
    EXPECT_EQ(made, 0) << "frame " << k;
  }
}

TEST(MapperAllocationTest, TheCounterSeesAnAllocation) {
  const long made = AllocationsOf([] {
    std::vector<double> values(1000, 1.0);
    EXPECT_EQ(values.size(), 1000u);
  });
  EXPECT_EQ(made, 1);
}

TEST(MapperAllocationTest, FsgpBgkAllocatesNothingOnceWarm) { ExpectNoAllocationOnceWarm({}); }

TEST(MapperAllocationTest, WithPcaAndWithoutFusionItAllocatesNothingOnceWarm) {
  FsgpConfig config;
  config.pca = true;
  config.fuse = false;
  ExpectNoAllocationOnceWarm(config);
}

TEST(MapperAllocationTest, FsgpAccumulationAllocatesNothingOnceWarm) {
  FsgpConfig config;
  config.fuse = false;
  config.accumulate_frames = 3;
  ExpectNoAllocationOnceWarm(config);
}

}  // namespace
}  // namespace trav::mapping
