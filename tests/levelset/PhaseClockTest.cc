// The phases of a run timed one after another (core/PhaseClock.h).

#include <levelfuse/core/PhaseClock.h>

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

namespace levelfuse {
namespace {

void busyFor(std::chrono::milliseconds span) {
  const auto end = std::chrono::steady_clock::now() + span;
  volatile double sink = 0.0;
  while (std::chrono::steady_clock::now() < end) sink = sink + 1.0;
}

TEST(PhaseClock, EachPhaseIsListedOnceInTheOrderFirstEnteredAndAddsUp) {
  PhaseClock clock;
  EXPECT_TRUE(clock.phases().empty());
  clock.enter("loading");
  busyFor(std::chrono::milliseconds(20));
  clock.enter("meshing");
  std::this_thread::sleep_for(std::chrono::milliseconds(30));  // wall time, next to no CPU time
  clock.enter("loading");
  busyFor(std::chrono::milliseconds(20));
  clock.stop();
  clock.stop();  // nothing current: nothing more
  ASSERT_EQ(clock.phases().size(), 2u);
  const PhaseTime& loading = clock.phases()[0];
  const PhaseTime& meshing = clock.phases()[1];
  EXPECT_EQ(loading.name, "loading");
  EXPECT_EQ(meshing.name, "meshing");
  EXPECT_GE(loading.seconds, 0.040);
  EXPECT_GE(meshing.seconds, 0.030);
  EXPECT_GT(loading.cpuSeconds, 0.0);
  EXPECT_LT(meshing.cpuSeconds, meshing.seconds);
}

TEST(PhaseClock, TheProcessCpuTimeOnlyGrows) {
  const double before = processCpuSeconds();
  busyFor(std::chrono::milliseconds(20));
  EXPECT_GT(processCpuSeconds(), before);
}

}  // namespace
}  // namespace levelfuse
