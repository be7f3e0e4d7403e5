// ControllerFrameView: the [can] frame map from the controller's side. What the emulator encodes
// it decodes (up to the scales' rounding), what it encodes the emulator decodes, its trigger
// frames are the emulator's power events, and bad frames are counted, not applied.
#include "io/can/can_controller_view.hpp"

#include <gtest/gtest.h>

#include <array>
#include <span>

#include "io/config/config_loader.hpp"
#include "malloc_guard.hpp"
#include "test_configs.hpp"

namespace ambdrop::can_controller_view_test {
namespace {

class ControllerFrameViewTest : public ::testing::Test {
 protected:
  void SetUp() override {
    config_ = LoadConfig(testing::ConfigPath("jarroux2019_industrial_pid_can.toml"));
    ASSERT_TRUE(config_.can.has_value());
  }
  const FrameMap& map() const { return config_.can->frame_map; }
  LoadedConfig config_;
};

TEST_F(ControllerFrameViewTest, DecodesWhatTheEmulatorEncodesToWithinHalfACount) {
  const ControllerFrameView view(map());
  EmulatorOutputs sent;
  sent.sensor_xy_m[0] = {12.34e-6, -101.26e-6};
  sent.sensor_xy_m[1] = {-0.5e-6, 2.9e-3};
  sent.power_on = false;
  sent.in_contact = true;
  sent.step = 70000;  // beyond the 2-byte counter: arrives modulo 65536
  sent.spin_speed_rad_s = 680.68;
  std::array<CanFrame, kMaxCanFrames> frames{};
  FrameMapCounters emulator;
  const std::size_t count = map().Encode(sent, frames, &emulator);
  ASSERT_EQ(count, 2u);  // sensors 0x200, status 0x300

  EmulatorOutputs got;
  FrameMapCounters controller;
  for (std::size_t f = 0; f < count; ++f) {
    ASSERT_EQ(view.Decode(frames[f], &got, &controller), DecodeResult::kApplied);
  }
  for (int s = 0; s < 2; ++s) {
    for (int axis = 0; axis < 2; ++axis) {
      EXPECT_NEAR(got.sensor_xy_m[s][axis], sent.sensor_xy_m[s][axis], 0.5e-7 + 1e-15)
          << "sensor " << s << " axis " << axis;
    }
  }
  EXPECT_FALSE(got.power_on);
  EXPECT_TRUE(got.in_contact);
  EXPECT_EQ(got.step, 70000u % 65536u);
  EXPECT_NEAR(got.spin_speed_rad_s, 680.68, 0.05 + 1e-9);
  EXPECT_EQ(controller.decoded, 2u);
  // The sensor set is complete with the sensor frame (0x200), not with the status frame.
  EXPECT_TRUE(view.CompletesSensors(frames[0]));
  EXPECT_FALSE(view.CompletesSensors(frames[1]));
}

TEST_F(ControllerFrameViewTest, EncodesCurrentsTheEmulatorDecodesAndSaturatesOutOfRange) {
  const ControllerFrameView view(map());
  ASSERT_EQ(view.current_frame_count(), 1u);
  CanCommand sent;
  sent.current_A[0] = {1.2344, -0.0006};
  sent.current_A[1] = {-11.9996, 40.0};  // 40 A is beyond int16 at 1 mA: saturates
  std::array<CanFrame, 4> frames{};
  FrameMapCounters controller;
  ASSERT_EQ(view.EncodeCurrents(sent, frames, &controller), 1u);
  EXPECT_EQ(frames[0].id, 0x100u);
  EXPECT_EQ(frames[0].len, 8);
  EXPECT_EQ(controller.saturated, 1u);

  CanCommand got;
  FrameMapCounters emulator;
  ASSERT_EQ(map().Decode(frames[0], &got, &emulator), DecodeResult::kApplied);
  EXPECT_DOUBLE_EQ(got.current_A[0][0], 1.234);
  EXPECT_DOUBLE_EQ(got.current_A[0][1], -0.001);  // -0.6 counts round to -1
  EXPECT_DOUBLE_EQ(got.current_A[1][0], -12.0);
  EXPECT_DOUBLE_EQ(got.current_A[1][1], 32.767);  // the raw maximum
  EXPECT_TRUE(got.power_on);
}

TEST_F(ControllerFrameViewTest, TriggerFramesAreTheEmulatorsPowerEvents) {
  const ControllerFrameView view(map());
  CanFrame fail;
  CanFrame restore;
  ASSERT_TRUE(view.EncodeTrigger(false, &fail));
  ASSERT_TRUE(view.EncodeTrigger(true, &restore));
  EXPECT_EQ(fail.id, 0x080u);
  EXPECT_EQ(fail.len, 1);
  EXPECT_EQ(fail.data[0], 0x01);  // what `cansend vcan0 080#01` sends
  EXPECT_EQ(restore.data[0], 0x02);

  CanCommand command;
  FrameMapCounters counters;
  ASSERT_EQ(map().Decode(fail, &command, &counters), DecodeResult::kApplied);
  EXPECT_FALSE(command.power_on);
  EXPECT_EQ(command.power_fail_frames, 1u);
  ASSERT_EQ(map().Decode(restore, &command, &counters), DecodeResult::kApplied);
  EXPECT_TRUE(command.power_on);
  EXPECT_EQ(command.power_restore_frames, 1u);
}

TEST_F(ControllerFrameViewTest, UnknownAndShortFramesAreCountedAndChangeNothing) {
  const ControllerFrameView view(map());
  EmulatorOutputs outputs;
  outputs.sensor_xy_m[0] = {1e-6, 2e-6};
  const EmulatorOutputs before = outputs;
  FrameMapCounters counters;
  CanFrame unknown;
  unknown.id = 0x100;  // the controller's own currents: not something it receives
  unknown.len = 8;
  EXPECT_EQ(view.Decode(unknown, &outputs, &counters), DecodeResult::kUnknownId);
  CanFrame short_sensors;
  short_sensors.id = 0x200;
  short_sensors.len = 7;
  short_sensors.data.fill(0x7F);
  EXPECT_EQ(view.Decode(short_sensors, &outputs, &counters), DecodeResult::kMalformed);
  CanFrame remote;
  remote.id = 0x200;
  remote.rtr = true;
  remote.len = 8;
  EXPECT_EQ(view.Decode(remote, &outputs, &counters), DecodeResult::kMalformed);
  EXPECT_EQ(counters.unknown_id, 1u);
  EXPECT_EQ(counters.malformed, 2u);
  EXPECT_EQ(counters.decoded, 0u);
  EXPECT_EQ(outputs.sensor_xy_m, before.sensor_xy_m);
}

TEST_F(ControllerFrameViewTest, FiltersPassExactlyTheEmulatorsFrames) {
  const ControllerFrameView view(map());
  const std::vector<CanFilter> filters = view.InputFilters();
  EXPECT_TRUE(CanFiltersAccept(filters, false, 0x200));
  EXPECT_TRUE(CanFiltersAccept(filters, false, 0x300));
  EXPECT_FALSE(CanFiltersAccept(filters, false, 0x100));
  EXPECT_FALSE(CanFiltersAccept(filters, false, 0x080));
}

TEST_F(ControllerFrameViewTest, DecodeAndEncodeDoNotAllocate) {
  if (!testing::MallocGuard::Available()) GTEST_SKIP() << "sanitizer build: malloc not hooked";
  const ControllerFrameView view(map());
  std::array<CanFrame, kMaxCanFrames> frames{};
  EmulatorOutputs outputs;
  CanCommand command;
  FrameMapCounters counters;
  const std::size_t count = map().Encode(outputs, frames, &counters);
  std::int64_t allocations = 0;
  {
    testing::MallocGuard guard;
    for (int i = 0; i < 1000; ++i) {
      for (std::size_t f = 0; f < count; ++f) (void)view.Decode(frames[f], &outputs, &counters);
      command.current_A[0][0] = 0.001 * i;
      (void)view.EncodeCurrents(command, std::span<CanFrame>(frames).subspan(count), &counters);
    }
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0);
}

}  // namespace
}  // namespace ambdrop::can_controller_view_test
