// The frame map: raw codecs for every width, signedness and byte order (fixed-seed random round
// trips), scaling with saturation counts, decode of unknown/short frames counted and harmless,
// triggers and status, allocation-free decode/encode, and the [can] config with its errors.
#include "io/can/can_frame_map.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "io/config/config_can.hpp"
#include "io/config/config_loader.hpp"
#include "malloc_guard.hpp"

namespace ambdrop::can_frame_map_test {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

constexpr char kSource[] = "test.toml";
using Payload = std::array<std::uint8_t, kCanFdMaxLen>;

// ---------------------------------------------------------------------------------------------
// Raw codec

struct LayoutCase {
  int width;
  bool is_signed;
  CanByteOrder order;
};

std::vector<LayoutCase> AllLayouts() {
  std::vector<LayoutCase> cases;
  for (const int width : {1, 2, 4}) {
    for (const bool is_signed : {false, true}) {
      for (const CanByteOrder order : {CanByteOrder::kLittle, CanByteOrder::kBig}) {
        cases.push_back({width, is_signed, order});
      }
    }
  }
  return cases;
}

std::string Describe(const LayoutCase& c) {
  return std::to_string(c.width) + (c.is_signed ? " signed " : " unsigned ") +
         (c.order == CanByteOrder::kLittle ? "little" : "big");
}

TEST(CanRawCodec, RandomRoundTripForEveryWidthSignednessAndByteOrder) {
  std::mt19937_64 rng(4242);
  for (const LayoutCase& c : AllLayouts()) {
    for (int offset = 0; offset + c.width <= kCanFdMaxLen; offset += 7) {
      const CanSignalLayout layout{.byte_offset = offset,
                                   .width_bytes = c.width,
                                   .is_signed = c.is_signed,
                                   .byte_order = c.order};
      std::uniform_int_distribution<std::int64_t> raw_of(RawMin(layout), RawMax(layout));
      for (int trial = 0; trial < 200; ++trial) {
        // Either an extreme or a random value.
        const std::int64_t raw = trial == 0   ? RawMin(layout)
                                 : trial == 1 ? RawMax(layout)
                                 : trial == 2 ? 0
                                              : raw_of(rng);
        Payload data;
        data.fill(0xA5);
        WriteRaw(layout, raw, data);
        ASSERT_EQ(ReadRaw(layout, data), raw) << Describe(c) << " at " << offset;
        // No byte outside the signal was touched.
        for (int i = 0; i < kCanFdMaxLen; ++i) {
          if (i < offset || i >= offset + c.width) {
            ASSERT_EQ(data[static_cast<std::size_t>(i)], 0xA5) << Describe(c);
          }
        }
      }
    }
  }
}

TEST(CanRawCodec, BytePatterns) {
  Payload data{};
  CanSignalLayout layout{.byte_offset = 1, .width_bytes = 2};
  WriteRaw(layout, 0x1234, data);
  EXPECT_EQ(data[1], 0x34);
  EXPECT_EQ(data[2], 0x12);
  layout.byte_order = CanByteOrder::kBig;
  WriteRaw(layout, 0x1234, data);
  EXPECT_EQ(data[1], 0x12);
  EXPECT_EQ(data[2], 0x34);

  layout = CanSignalLayout{.byte_offset = 0, .width_bytes = 2, .is_signed = true};
  WriteRaw(layout, -2, data);
  EXPECT_EQ(data[0], 0xFE);
  EXPECT_EQ(data[1], 0xFF);
  layout.is_signed = false;
  EXPECT_EQ(ReadRaw(layout, data), 0xFFFE);  // the same bytes, unsigned

  layout = CanSignalLayout{.byte_offset = 4, .width_bytes = 4, .byte_order = CanByteOrder::kBig};
  WriteRaw(layout, 0x01020304, data);
  EXPECT_EQ(data[4], 0x01);
  EXPECT_EQ(data[7], 0x04);

  EXPECT_EQ(RawMin({.width_bytes = 1, .is_signed = true}), -128);
  EXPECT_EQ(RawMax({.width_bytes = 1, .is_signed = true}), 127);
  EXPECT_EQ(RawMax({.width_bytes = 2}), 65535);
  EXPECT_EQ(RawMin({.width_bytes = 4, .is_signed = true}), -2147483648LL);
  EXPECT_EQ(RawMax({.width_bytes = 4}), 4294967295LL);
}

TEST(CanScaling, PhysicalRoundTripWithinHalfACount) {
  std::mt19937_64 rng(7);
  for (const LayoutCase& c : AllLayouts()) {
    const CanSignalLayout layout{
        .width_bytes = c.width, .is_signed = c.is_signed, .byte_order = c.order};
    const CanScaling scaling{.scale = 2.5e-4, .offset = -0.125};
    const double low = RawToPhysical(scaling, RawMin(layout));
    const double high = RawToPhysical(scaling, RawMax(layout));
    std::uniform_real_distribution<double> physical_of(low, high);
    for (int trial = 0; trial < 500; ++trial) {
      const double physical = physical_of(rng);
      bool saturated = true;
      const std::int64_t raw = PhysicalToRaw(layout, scaling, physical, &saturated);
      EXPECT_FALSE(saturated) << Describe(c);
      EXPECT_LE(std::abs(RawToPhysical(scaling, raw) - physical), 0.5 * scaling.scale + 1e-12)
          << Describe(c);
    }
  }
}

TEST(CanScaling, SaturatesAndFlagsOutOfRangeAndNonFinite) {
  const CanSignalLayout layout{.width_bytes = 1, .is_signed = true};
  const CanScaling scaling{.scale = 0.5, .offset = 0.0};
  bool saturated = false;
  EXPECT_EQ(PhysicalToRaw(layout, scaling, 63.5, &saturated), 127);
  EXPECT_FALSE(saturated);
  EXPECT_EQ(PhysicalToRaw(layout, scaling, 63.8, &saturated), 127);  // rounds to 128: clamped
  EXPECT_TRUE(saturated);
  EXPECT_EQ(PhysicalToRaw(layout, scaling, -1e300, &saturated), -128);
  EXPECT_TRUE(saturated);
  EXPECT_EQ(PhysicalToRaw(layout, scaling, std::numeric_limits<double>::quiet_NaN(), &saturated),
            0);
  EXPECT_TRUE(saturated);
  EXPECT_EQ(PhysicalToRaw(layout, scaling, -std::numeric_limits<double>::infinity(), &saturated),
            0);
  EXPECT_TRUE(saturated);
  // Ties go to even.
  const CanScaling unit{.scale = 1.0, .offset = 0.0};
  EXPECT_EQ(PhysicalToRaw(layout, unit, 0.5, &saturated), 0);
  EXPECT_EQ(PhysicalToRaw(layout, unit, 1.5, &saturated), 2);
  EXPECT_EQ(PhysicalToRaw(layout, unit, -2.5, &saturated), -2);
}

// ---------------------------------------------------------------------------------------------
// Frame map built in code: emulator ↔ a mirrored "controller" map over the same layouts

/// Emulator map: sensors (3 sensors x 2 axes) with the given layouts, one frame each; and the
/// controller's view: currents of 3 AMBs at exactly those layouts and scalings.
struct MirroredMaps {
  FrameMap emulator;
  FrameMap controller;
  std::vector<CanSignalLayout> layouts;
  std::vector<CanScaling> scalings;
};

MirroredMaps Mirror(const std::vector<LayoutCase>& cases, std::uint32_t first_id) {
  FrameMapSpec emulator;
  FrameMapSpec controller;
  emulator.sensor_names = {"s0", "s1", "s2"};
  controller.amb_names = {"a0", "a1", "a2"};
  MirroredMaps maps;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const LayoutCase& c = cases[k];
    const CanSignalLayout layout{.id = first_id + static_cast<std::uint32_t>(k),
                                 .extended = k % 3 == 2,
                                 .byte_offset = static_cast<int>(k % 3),
                                 .width_bytes = c.width,
                                 .is_signed = c.is_signed,
                                 .byte_order = c.order};
    const CanScaling scaling{.scale = 1e-3 * static_cast<double>(k + 1),
                             .offset = 0.25 * static_cast<double>(k)};
    CanSignalSpec signal;
    signal.role = CanSignalRole::kSensor;
    signal.layout = layout;
    signal.scaling = scaling;
    signal.index = static_cast<int>(k / 2);
    signal.axis = static_cast<int>(k % 2);
    signal.name = "sensor " + Describe(c);
    emulator.signals.push_back(signal);
    signal.role = CanSignalRole::kCurrent;
    signal.name = "current " + Describe(c);
    controller.signals.push_back(signal);
    maps.layouts.push_back(layout);
    maps.scalings.push_back(scaling);
  }
  maps.emulator = FrameMap(emulator);
  maps.controller = FrameMap(controller);
  return maps;
}

TEST(FrameMap, EncodeDecodeRoundTripForEveryLayout) {
  const std::vector<LayoutCase> all = AllLayouts();
  std::mt19937_64 rng(99);
  for (std::size_t half = 0; half < 2; ++half) {
    const std::vector<LayoutCase> cases(all.begin() + static_cast<long>(6 * half),
                                        all.begin() + static_cast<long>(6 * half + 6));
    const MirroredMaps maps = Mirror(cases, 0x300 + static_cast<std::uint32_t>(16 * half));
    ASSERT_EQ(maps.emulator.output_frame_count(), 6u);
    ASSERT_EQ(maps.controller.input_frame_count(), 6u);
    FrameMapCounters emulator_counters, controller_counters;
    std::array<CanFrame, 8> frames;
    for (int trial = 0; trial < 1000; ++trial) {
      EmulatorOutputs outputs;
      std::array<std::int64_t, 6> raws{};
      for (std::size_t k = 0; k < 6; ++k) {
        const CanSignalLayout& layout = maps.layouts[k];
        std::uniform_int_distribution<std::int64_t> raw_of(RawMin(layout), RawMax(layout));
        raws[k] = raw_of(rng);
        outputs.sensor_xy_m[k / 2][k % 2] = RawToPhysical(maps.scalings[k], raws[k]);
      }
      ASSERT_EQ(maps.emulator.Encode(outputs, frames, &emulator_counters), 6u);
      CanCommand command;
      for (std::size_t f = 0; f < 6; ++f) {
        ASSERT_TRUE(IsValid(frames[f]));
        ASSERT_EQ(maps.controller.Decode(frames[f], &command, &controller_counters),
                  DecodeResult::kApplied);
      }
      for (std::size_t k = 0; k < 6; ++k) {
        // The exact raw went over, so the decoded value is bit-identical to the sent one.
        EXPECT_EQ(command.current_A[k / 2][k % 2], outputs.sensor_xy_m[k / 2][k % 2])
            << Describe(cases[k]) << " raw " << raws[k];
      }
    }
    EXPECT_EQ(emulator_counters.saturated, 0u);
    EXPECT_EQ(emulator_counters.encoded_frames, 6000u);
    EXPECT_EQ(controller_counters.decoded, 6000u);
  }
}

TEST(FrameMap, SaturationsAreCountedPerSignal) {
  const MirroredMaps maps =
      Mirror({{1, false, CanByteOrder::kLittle}, {2, true, CanByteOrder::kBig}}, 0x300);
  EmulatorOutputs outputs;
  outputs.sensor_xy_m[0][0] = 1e9;   // far above 255 counts
  outputs.sensor_xy_m[0][1] = -1e9;  // far below -32768 counts
  std::array<CanFrame, 2> frames;
  FrameMapCounters counters;
  ASSERT_EQ(maps.emulator.Encode(outputs, frames, &counters), 2u);
  EXPECT_EQ(counters.saturated, 2u);
  EXPECT_EQ(counters.saturated_by_signal[0], 1u);
  EXPECT_EQ(counters.saturated_by_signal[1], 1u);
  EXPECT_EQ(frames[0].data[0], 0xFF);  // clamped to the largest count
  EXPECT_EQ(frames[1].data[1], 0x80);  // -32768 big-endian at byte offset 1: 80 00
  EXPECT_EQ(frames[1].data[2], 0x00);
  outputs.sensor_xy_m[0][0] = std::nan("");
  ASSERT_EQ(maps.emulator.Encode(outputs, frames, &counters), 2u);
  EXPECT_EQ(counters.saturated_by_signal[0], 2u);
  EXPECT_EQ(frames[0].data[0], 0x00);
}

TEST(FrameMap, EncodeStopsAtTheEndOfTheGivenBuffer) {
  const MirroredMaps maps =
      Mirror({{1, false, CanByteOrder::kLittle}, {2, true, CanByteOrder::kBig}}, 0x300);
  std::array<CanFrame, 1> frames;
  FrameMapCounters counters;
  EXPECT_EQ(maps.emulator.Encode(EmulatorOutputs{}, frames, &counters), 1u);
  EXPECT_EQ(frames[0].id, 0x300u);
}

TEST(FrameMap, DuplicateQuantitiesAreRejected) {
  FrameMapSpec spec;
  spec.sensor_names = {"s"};
  CanSignalSpec signal;
  signal.role = CanSignalRole::kSensor;
  signal.layout = {.id = 0x10, .width_bytes = 2};
  signal.name = "first";
  signal.location = "here.toml:3";
  spec.signals.push_back(signal);
  signal.layout.id = 0x11;
  signal.name = "second";
  signal.location = "here.toml:9";
  spec.signals.push_back(signal);
  try {
    FrameMap map(spec);
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& error) {
    EXPECT_STREQ(error.what(),
                 "here.toml:9: signal 'second': a second sensor signal for the same quantity as "
                 "'first' (here.toml:3)");
  }
}

TEST(FrameMap, CapacitiesAreChecked) {
  FrameMapSpec spec;
  spec.amb_names = {"a", "b", "c", "d", "e"};
  EXPECT_THROW(FrameMap{spec}, ConfigError);
  spec = FrameMapSpec{};
  spec.sensor_names = {"s"};
  for (int i = 0; i < 2; ++i) {
    CanSignalSpec signal;
    signal.role = CanSignalRole::kSensor;
    signal.layout = {.id = 0x10, .byte_offset = 6, .width_bytes = 4};
    signal.axis = i;
    spec.signals.push_back(signal);
  }
  EXPECT_THROW(FrameMap{spec}, ConfigError);  // bytes 6..9 do not fit 8
  spec.fd = true;
  spec.signals[1].layout.byte_offset = 10;
  EXPECT_NO_THROW(FrameMap{spec});
  const FrameMap fd_map(spec);
  ASSERT_EQ(fd_map.OutputFrames().size(), 1u);
  EXPECT_EQ(fd_map.OutputFrames()[0].len, 16);  // 14 bytes used, rounded up to an FD length
}

// ---------------------------------------------------------------------------------------------
// Config-driven map

constexpr std::string_view kConfig = R"([can]
interface = "vcan0"
exchange_rate_Hz = 1000
byte_order = "little"

[can.currents_in.de.x]
id = 0x100
byte_offset = 0
width_bytes = 2
signed = true
scale_A_per_count = 0.001

[can.currents_in.de.y]
id = 0x100
byte_offset = 2
width_bytes = 2
signed = true
scale_A_per_count = 0.001

[can.currents_in.nde.x]
id = 0x101
byte_offset = 0
width_bytes = 2
signed = true
byte_order = "big"
scale_A_per_count = 0.001
offset_A = 0.5

[can.currents_in.nde.y]
id = 0x101
byte_offset = 2
width_bytes = 4
signed = true
byte_order = "big"
scale_A_per_count = 1e-6

[can.trigger_in.power_fail]
id = 0x080
byte_offset = 0
width_bytes = 1
mask = 0x01
value = 1

[can.trigger_in.power_restore]
id = 0x080
byte_offset = 0
width_bytes = 1
mask = 0x01
value = 0

[can.sensors_out.s_de.x]
id = 0x200
byte_offset = 0
width_bytes = 2
signed = true
scale_m_per_count = 1e-7

[can.sensors_out.s_de.y]
id = 0x200
byte_offset = 2
width_bytes = 2
signed = true
scale_m_per_count = 1e-7

[can.sensors_out.s_nde.x]
id = 0x201
byte_offset = 0
width_bytes = 2
scale_m_per_count = 1e-7
offset_m = -3.2768e-3

[can.sensors_out.s_nde.y]
id = 0x201
byte_offset = 2
width_bytes = 2
scale_m_per_count = 1e-7
offset_m = -3.2768e-3

[can.status_out.power_on]
id = 0x210
byte_offset = 0
width_bytes = 1

[can.status_out.in_contact]
id = 0x210
byte_offset = 1
width_bytes = 1

[can.status_out.step_counter]
id = 0x210
byte_offset = 2
width_bytes = 4

[can.status_out.spin_speed]
id = 0x18FF0211
extended = true
byte_offset = 0
width_bytes = 2
scale_rad_s_per_count = 0.1

[can.status_out.overrun_counter]
id = 0x18FF0211
extended = true
byte_offset = 2
width_bytes = 2
)";

/// 1-based line of the first line containing `needle` at or after line `from`.
int LineOf(std::string_view text, std::string_view needle, int from = 1) {
  int line = 1;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    if (line >= from && text.substr(start, end - start).find(needle) != std::string_view::npos) {
      return line;
    }
    start = end + 1;
    ++line;
  }
  ADD_FAILURE() << "no line with " << needle;
  return 0;
}

/// "test.toml:LINE" of that line.
std::string Loc(std::string_view text, std::string_view needle, int from = 1) {
  return std::string(kSource) + ":" + std::to_string(LineOf(text, needle, from));
}

/// The prefix of a message about that line.
std::string At(std::string_view text, std::string_view needle, int from = 1) {
  return Loc(text, needle, from) + ": ";
}

/// `text` with the first occurrence of `from` (at or after the line holding `after`) replaced.
std::string Replace(std::string_view text, std::string_view from, std::string_view to,
                    std::string_view after = "") {
  std::string out(text);
  const std::size_t anchor = after.empty() ? 0 : out.find(after);
  EXPECT_NE(anchor, std::string::npos) << after;
  const std::size_t at = out.find(from, anchor);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) out.replace(at, from.size(), to);
  return out;
}

std::string ErrorOf(const std::string& text, const CanNames* names = nullptr) {
  try {
    LoadCanConfigFromString(text, kSource, names);
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "no error";
}

CanFrame Frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
  CanFrame frame;
  frame.id = id;
  frame.len = static_cast<std::uint8_t>(bytes.size());
  std::size_t i = 0;
  for (const std::uint8_t byte : bytes) frame.data[i++] = byte;
  return frame;
}

TEST(CanConfig, LoadsTheFullSchema) {
  const CanConfig config = LoadCanConfigFromString(std::string(kConfig), kSource);
  EXPECT_EQ(config.interface, "vcan0");
  EXPECT_EQ(config.exchange_rate_Hz, 1000.0);
  EXPECT_FALSE(config.fd);
  EXPECT_FALSE(config.bit_rate_switch);
  EXPECT_EQ(config.bitrate_bps, 1e6);
  const FrameMapSpec& spec = config.frame_map.spec();
  EXPECT_EQ(spec.amb_names, (std::vector<std::string>{"de", "nde"}));
  EXPECT_EQ(spec.sensor_names, (std::vector<std::string>{"s_de", "s_nde"}));
  EXPECT_EQ(spec.signals.size(), 15u);
  EXPECT_EQ(spec.signals.front().name, "can.currents_in.de.x");
  EXPECT_EQ(spec.signals.front().location, Loc(kConfig, "[can.currents_in.de.x]"));
  EXPECT_EQ(config.frame_map.input_frame_count(), 3u);
  EXPECT_EQ(config.frame_map.output_frame_count(), 4u);

  // The worst-case bus load is the sum of the frame times at the exchange rate.
  double expected_s = 0.0;
  for (const auto& shapes : {config.frame_map.InputFrames(), config.frame_map.OutputFrames()}) {
    for (const CanFrameShape& shape : shapes) {
      expected_s += CanFrameWorstCaseTime_s(shape.extended, false, false, shape.len, 1e6, 1e6);
    }
  }
  EXPECT_DOUBLE_EQ(config.bus_load, expected_s * 1000.0);
  EXPECT_GT(config.bus_load, 0.4);
  EXPECT_LT(config.bus_load, 0.8);

  const SocketCanOptions options = config.SocketOptions();
  EXPECT_EQ(options.interface, "vcan0");
  EXPECT_FALSE(options.socket.fd_frames);
  EXPECT_EQ(options.socket.filters,
            (std::vector<CanFilter>{CanFilter::Exact(0x080, false), CanFilter::Exact(0x100, false),
                                    CanFilter::Exact(0x101, false)}));
}

TEST(CanConfig, DecodesCurrentsAndTriggers) {
  const FrameMap map = LoadCanConfigFromString(std::string(kConfig), kSource).frame_map;
  CanCommand command;
  FrameMapCounters counters;
  // de: x = -1000 counts, y = +1000 counts, little-endian.
  ASSERT_EQ(map.Decode(Frame(0x100, {0x18, 0xFC, 0xE8, 0x03}), &command, &counters),
            DecodeResult::kApplied);
  EXPECT_DOUBLE_EQ(command.current_A[0][0], -1.0);
  EXPECT_DOUBLE_EQ(command.current_A[0][1], 1.0);
  // nde: x = 1 count + 0.5 A, y = -2 000 000 counts of 1 uA, big-endian.
  ASSERT_EQ(map.Decode(Frame(0x101, {0x00, 0x01, 0xFF, 0xE1, 0x7B, 0x80}), &command, &counters),
            DecodeResult::kApplied);
  EXPECT_DOUBLE_EQ(command.current_A[1][0], 0.501);
  EXPECT_DOUBLE_EQ(command.current_A[1][1], -2.0);

  EXPECT_TRUE(command.power_on);
  ASSERT_EQ(map.Decode(Frame(0x080, {0x03}), &command, &counters), DecodeResult::kApplied);
  EXPECT_FALSE(command.power_on);  // bit 0 set: power fails (the other bits are masked off)
  EXPECT_EQ(command.power_fail_frames, 1u);
  ASSERT_EQ(map.Decode(Frame(0x080, {0xFE}), &command, &counters), DecodeResult::kApplied);
  EXPECT_TRUE(command.power_on);
  EXPECT_EQ(command.power_restore_frames, 1u);
  EXPECT_EQ(counters.decoded, 4u);
  EXPECT_EQ(counters.trigger_no_match, 0u);
}

TEST(CanConfig, UnknownAndMalformedFramesAreCountedAndChangeNothing) {
  const FrameMap map = LoadCanConfigFromString(std::string(kConfig), kSource).frame_map;
  CanCommand command;
  command.current_A[1][0] = 7.0;
  const CanCommand before = command;
  FrameMapCounters counters;
  EXPECT_EQ(map.Decode(Frame(0x102, {1, 2, 3, 4}), &command, &counters), DecodeResult::kUnknownId);
  CanFrame extended = Frame(0x100, {1, 2, 3, 4});
  extended.extended = true;  // same number, other format: another frame
  EXPECT_EQ(map.Decode(extended, &command, &counters), DecodeResult::kUnknownId);
  // 0x101 needs 6 bytes; 5 is short. Nothing of it is applied.
  EXPECT_EQ(map.Decode(Frame(0x101, {0, 9, 0, 0, 0}), &command, &counters),
            DecodeResult::kMalformed);
  CanFrame remote = Frame(0x100, {0, 0, 0, 0});
  remote.rtr = true;
  EXPECT_EQ(map.Decode(remote, &command, &counters), DecodeResult::kMalformed);
  EXPECT_EQ(map.Decode(Frame(0x080, {}), &command, &counters), DecodeResult::kMalformed);
  // Sent frames (our own, looped back) are unknown to the decoder too.
  EXPECT_EQ(map.Decode(Frame(0x200, {0, 0, 0, 0}), &command, &counters), DecodeResult::kUnknownId);
  EXPECT_EQ(counters.unknown_id, 3u);
  EXPECT_EQ(counters.malformed, 3u);
  EXPECT_EQ(counters.decoded, 0u);
  EXPECT_EQ(command.current_A, before.current_A);
  EXPECT_TRUE(command.power_on);
  // Longer than needed is fine (a controller may always send 8 bytes).
  EXPECT_EQ(map.Decode(Frame(0x100, {0, 0, 0, 0, 9, 9, 9, 9}), &command, &counters),
            DecodeResult::kApplied);
}

TEST(CanConfig, EncodesSensorsAndStatus) {
  const FrameMap map = LoadCanConfigFromString(std::string(kConfig), kSource).frame_map;
  EmulatorOutputs outputs;
  outputs.sensor_xy_m[0] = {12.3e-6, -0.1e-6};  // 123 and -1 counts
  outputs.sensor_xy_m[1] = {0.0, 1e-6};         // ADC-like: 32768 and 32778 counts
  outputs.power_on = false;
  outputs.in_contact = true;
  outputs.step = 0x1'0000'0005;  // wraps in 4 bytes
  outputs.spin_speed_rad_s = 314.159;
  outputs.overruns = 0x12345;  // wraps in 2 bytes
  std::array<CanFrame, 8> frames;
  FrameMapCounters counters;
  ASSERT_EQ(map.Encode(outputs, frames, &counters), 4u);
  EXPECT_EQ(counters.saturated, 0u);

  const auto bytes = [](const CanFrame& frame) {
    return std::vector<int>(frame.data.begin(), frame.data.begin() + frame.len);
  };
  EXPECT_EQ(frames[0].id, 0x200u);
  EXPECT_EQ(bytes(frames[0]), (std::vector<int>{0x7B, 0x00, 0xFF, 0xFF}));
  EXPECT_EQ(frames[1].id, 0x201u);
  EXPECT_EQ(bytes(frames[1]), (std::vector<int>{0x00, 0x80, 0x0A, 0x80}));
  EXPECT_EQ(frames[2].id, 0x210u);
  EXPECT_EQ(bytes(frames[2]), (std::vector<int>{0, 1, 5, 0, 0, 0}));
  EXPECT_EQ(frames[3].id, 0x18FF0211u);
  EXPECT_TRUE(frames[3].extended);
  EXPECT_EQ(bytes(frames[3]), (std::vector<int>{0x46, 0x0C, 0x45, 0x23}));  // 3142, 0x2345
  for (const CanFrame& frame : frames) EXPECT_FALSE(frame.fd);
}

TEST(CanConfig, TxLengthAndFdFrames) {
  std::string text =
      Replace(kConfig, "byte_order = \"little\"\n", "byte_order = \"little\"\ntx_len_bytes = 8\n");
  FrameMap map = LoadCanConfigFromString(text, kSource).frame_map;
  for (const CanFrameShape& shape : map.OutputFrames()) EXPECT_EQ(shape.len, 8);

  text = Replace(kConfig, "byte_order = \"little\"\n",
                 "byte_order = \"little\"\nfd = true\ndata_bitrate_bps = 5e6\n");
  text = Replace(text, "byte_offset = 2\nwidth_bytes = 2", "byte_offset = 40\nwidth_bytes = 2",
                 "[can.sensors_out.s_de.y]");
  const CanConfig config = LoadCanConfigFromString(text, kSource);
  EXPECT_TRUE(config.fd);
  EXPECT_TRUE(config.bit_rate_switch);  // the default with FD
  std::array<CanFrame, 8> frames;
  FrameMapCounters counters;
  ASSERT_EQ(config.frame_map.Encode(EmulatorOutputs{}, frames, &counters), 4u);
  EXPECT_TRUE(frames[0].fd);
  EXPECT_TRUE(frames[0].brs);
  EXPECT_EQ(frames[0].len, 48);  // 42 bytes used
  EXPECT_TRUE(IsValid(frames[0]));
}

TEST(CanConfig, NamesFromTheModelSetTheIndices) {
  const CanNames names{.ambs = {"nde", "de"}, .sensors = {"s_nde", "s_mid", "s_de"}};
  const CanConfig config = LoadCanConfigFromString(std::string(kConfig), kSource, &names);
  EXPECT_EQ(config.frame_map.spec().amb_names, names.ambs);
  CanCommand command;
  FrameMapCounters counters;
  ASSERT_EQ(config.frame_map.Decode(Frame(0x100, {0x18, 0xFC, 0, 0}), &command, &counters),
            DecodeResult::kApplied);
  EXPECT_DOUBLE_EQ(command.current_A[1][0], -1.0);  // "de" is the model's second AMB
  EmulatorOutputs outputs;
  outputs.sensor_xy_m[2][0] = 12.3e-6;  // "s_de" is the model's third sensor
  std::array<CanFrame, 4> frames;
  ASSERT_EQ(config.frame_map.Encode(outputs, frames, &counters), 4u);
  EXPECT_EQ(frames[0].data[0], 0x7B);
}

TEST(CanConfig, TriggerWithoutMatchIsCountedAndAnyFrameTriggers) {
  std::string text = Replace(kConfig, "[can.trigger_in.power_restore]\nid = 0x080",
                             "[can.trigger_in.power_restore]\nid = 0x081\nany_frame = true");
  text = Replace(text, "byte_offset = 0\nwidth_bytes = 1\nmask = 0x01\nvalue = 0\n", "");
  const FrameMap map = LoadCanConfigFromString(text, kSource).frame_map;
  CanCommand command;
  FrameMapCounters counters;
  ASSERT_EQ(map.Decode(Frame(0x080, {0x00}), &command, &counters), DecodeResult::kApplied);
  EXPECT_EQ(counters.trigger_no_match, 1u);
  EXPECT_TRUE(command.power_on);
  ASSERT_EQ(map.Decode(Frame(0x080, {0x01}), &command, &counters), DecodeResult::kApplied);
  EXPECT_FALSE(command.power_on);
  ASSERT_EQ(map.Decode(Frame(0x081, {}), &command, &counters), DecodeResult::kApplied);
  EXPECT_TRUE(command.power_on);  // any frame on 0x081, even an empty one
}

TEST(CanConfig, DecodeAndEncodeDoNotAllocate) {
  const FrameMap map = LoadCanConfigFromString(std::string(kConfig), kSource).frame_map;
  const std::array<CanFrame, 5> received = {Frame(0x100, {1, 2, 3, 4}),
                                            Frame(0x101, {1, 2, 3, 4, 5, 6}), Frame(0x080, {1}),
                                            Frame(0x7FF, {}), Frame(0x101, {1})};
  std::array<CanFrame, 8> sent;
  CanCommand command;
  FrameMapCounters counters;
  EmulatorOutputs outputs;
  std::int64_t allocations = 0;
  {
    testing::MallocGuard guard;
    for (int i = 0; i < 2000; ++i) {
      for (const CanFrame& frame : received) (void)map.Decode(frame, &command, &counters);
      outputs.step = static_cast<std::uint64_t>(i);
      outputs.sensor_xy_m[0][0] = 1e-6 * i;
      (void)map.Encode(outputs, sent, &counters);
    }
    allocations = guard.allocations();
  }
  EXPECT_EQ(counters.decoded, 6000u);
  EXPECT_EQ(counters.encoded_frames, 8000u);
  EXPECT_EQ(allocations, 0);
}

TEST(CanConfig, FrameTimes) {
  // 11-bit, 8 bytes: 34 + 64 + 13 + floor(97/4) = 135 bits, so ~7 400 frames/s at 1 Mbit/s.
  EXPECT_DOUBLE_EQ(CanFrameWorstCaseTime_s(false, false, false, 8, 1e6, 1e6), 135e-6);
  EXPECT_DOUBLE_EQ(CanFrameWorstCaseTime_s(true, false, false, 8, 1e6, 1e6), 160e-6);
  EXPECT_DOUBLE_EQ(CanFrameWorstCaseTime_s(false, false, false, 0, 5e5, 5e5), 110e-6);
  // FD with a faster data phase beats FD without it, and 64 bytes beat 8 classic frames.
  const double fd_brs = CanFrameWorstCaseTime_s(false, true, true, 64, 1e6, 5e6);
  const double fd_slow = CanFrameWorstCaseTime_s(false, true, false, 64, 1e6, 5e6);
  EXPECT_LT(fd_brs, fd_slow);
  EXPECT_LT(fd_brs, 8 * 135e-6);
  EXPECT_GT(fd_slow, 64 * 8 * 1e-6);
}

TEST(CanConfig, LoadsFromAFile) {
  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "ambdrop_can_config_test.toml";
  {
    std::ofstream file(path);
    file << kConfig;
  }
  EXPECT_EQ(LoadCanConfig(path).interface, "vcan0");
  std::filesystem::remove(path);
  try {
    LoadCanConfig(path);
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& error) {
    EXPECT_THAT(error.what(), HasSubstr("cannot open the config file"));
  }
}

// Each rule of the schema, with the file, line, key, value found and what was expected.

TEST(CanConfigErrors, UnknownKeys) {
  EXPECT_THAT(ErrorOf(Replace(kConfig, "byte_order = \"little\"", "byte_ordr = \"little\"")),
              StartsWith(At(kConfig, "byte_order = \"little\"") +
                         "unknown key 'can.byte_ordr' (allowed here: interface, exchange_rate_Hz, "
                         "fd, bit_rate_switch, bitrate_bps,"));
  const std::string text =
      Replace(kConfig, "scale_A_per_count = 0.001", "scale = 0.001", "[can.currents_in.de.x]");
  EXPECT_EQ(ErrorOf(text),
            At(text, "scale = 0.001") +
                "unknown key 'can.currents_in.de.x.scale' (allowed here: id, extended, "
                "byte_offset, width_bytes, signed, byte_order, scale_A_per_count, offset_A)");
  EXPECT_THAT(ErrorOf(Replace(kConfig, "[can.currents_in.de.y]", "[can.currents_in.de.z]")),
              HasSubstr("unknown key 'can.currents_in.de.z' (allowed here: x, y)"));
  EXPECT_THAT(ErrorOf(Replace(kConfig, "[can.status_out.spin_speed]", "[can.status_out.speed]")),
              HasSubstr("unknown key 'can.status_out.speed' (allowed here: in_contact, "
                        "overrun_counter, power_on, spin_speed, step_counter)"));
  // Triggers compare unsigned bits: no "signed" key.
  const std::string signed_trigger =
      Replace(kConfig, "mask = 0x01\nvalue = 1", "mask = 0x01\nvalue = 1\nsigned = true");
  EXPECT_EQ(ErrorOf(signed_trigger),
            At(signed_trigger, "signed = true", LineOf(kConfig, "[can.trigger_in.power_fail]")) +
                "unknown key 'can.trigger_in.power_fail.signed' (allowed here: id, extended, "
                "byte_offset, width_bytes, byte_order, mask, value, any_frame)");
  // any_frame leaves only the id.
  EXPECT_THAT(ErrorOf(Replace(kConfig, "mask = 0x01\nvalue = 1", "any_frame = true")),
              HasSubstr("unknown key 'can.trigger_in.power_fail.byte_offset' (allowed here: id, "
                        "extended, any_frame)"));
}

TEST(CanConfigErrors, Layout) {
  const int de_x = LineOf(kConfig, "[can.currents_in.de.x]");
  std::string text = Replace(kConfig, "width_bytes = 2", "width_bytes = 3");
  EXPECT_EQ(ErrorOf(text), At(text, "width_bytes = 3") +
                               "key 'can.currents_in.de.x.width_bytes': expected 1, 2 or 4, "
                               "found 3");
  text = Replace(kConfig, "width_bytes = 2", "width_bytes = 8");
  EXPECT_EQ(ErrorOf(text), At(text, "width_bytes = 8") +
                               "key 'can.currents_in.de.x.width_bytes': expected an integer in "
                               "[1, 4], found 8");
  text = Replace(kConfig, "id = 0x100", "id = 0x800");
  EXPECT_EQ(ErrorOf(text), At(text, "id = 0x800") +
                               "key 'can.currents_in.de.x.id': expected an 11-bit identifier "
                               "(extended = false) in [0x0, 0x7ff], found 2048");
  text = Replace(kConfig, "id = 0x18FF0211", "id = 0x38FF0211");
  EXPECT_EQ(ErrorOf(text), At(text, "id = 0x38FF0211") +
                               "key 'can.status_out.spin_speed.id': expected a 29-bit identifier "
                               "(extended = true) in [0x0, 0x1fffffff], found 956236305");
  text = Replace(kConfig, "byte_offset = 0", "byte_offset = 7");
  EXPECT_EQ(ErrorOf(text), At(text, "byte_offset = 7") +
                               "key 'can.currents_in.de.x.byte_offset': expected an offset at "
                               "most 6 (width_bytes = 2, 8 bytes of a classic CAN payload), "
                               "found 7");
  text = Replace(kConfig, "byte_offset = 0", "byte_offset = -1");
  EXPECT_THAT(ErrorOf(text), HasSubstr("key 'can.currents_in.de.x.byte_offset': expected an "
                                       "integer in [0, 7], found -1"));
  text = Replace(kConfig, "id = 0x100\n", "");
  EXPECT_EQ(ErrorOf(text), std::string(kSource) + ":" + std::to_string(de_x) +
                               ": missing key 'can.currents_in.de.x.id': expected an 11-bit "
                               "identifier (extended = false) in [0x0, 0x7ff]");
  text = Replace(kConfig, "signed = true", "signed = \"yes\"");
  EXPECT_EQ(ErrorOf(text), At(text, "signed = \"yes\"") +
                               "key 'can.currents_in.de.x.signed': expected a boolean (true or "
                               "false), found \"yes\"");
  text = Replace(kConfig, "byte_order = \"big\"", "byte_order = \"motorola\"");
  EXPECT_EQ(ErrorOf(text), At(text, "byte_order = \"motorola\"") +
                               "key 'can.currents_in.nde.x.byte_order': expected one of "
                               "\"little\", \"big\", found \"motorola\"");
}

TEST(CanConfigErrors, Scaling) {
  std::string text = Replace(kConfig, "scale_A_per_count = 0.001", "scale_A_per_count = 0");
  EXPECT_EQ(ErrorOf(text), At(text, "scale_A_per_count = 0") +
                               "key 'can.currents_in.de.x.scale_A_per_count': expected a non-zero "
                               "finite number (A/count), found 0");
  text = Replace(kConfig, "scale_m_per_count = 1e-7", "scale_m_per_count = nan");
  EXPECT_THAT(ErrorOf(text), HasSubstr("key 'can.sensors_out.s_de.x.scale_m_per_count': "
                                       "expected a non-zero finite number (m/count), found "
                                       "nan"));
  text = Replace(kConfig, "offset_A = 0.5", "offset_A = \"half\"");
  EXPECT_EQ(ErrorOf(text), At(text, "offset_A") +
                               "key 'can.currents_in.nde.x.offset_A': expected a finite number "
                               "(A), found \"half\"");
  text = Replace(kConfig, "scale_rad_s_per_count = 0.1\n", "");
  EXPECT_THAT(ErrorOf(text), HasSubstr("missing key 'can.status_out.spin_speed."
                                       "scale_rad_s_per_count': expected a non-zero finite "
                                       "number ((rad/s)/count)"));
}

TEST(CanConfigErrors, Triggers) {
  std::string text = Replace(kConfig, "mask = 0x01\nvalue = 1", "mask = 0x01\nvalue = 2");
  EXPECT_EQ(ErrorOf(text), At(text, "value = 2") +
                               "key 'can.trigger_in.power_fail.value': expected a value within "
                               "mask = 0x1 (else it never matches), found 2");
  text = Replace(kConfig, "mask = 0x01\nvalue = 1", "mask = 0x100\nvalue = 1");
  EXPECT_EQ(ErrorOf(text), At(text, "mask = 0x100") +
                               "key 'can.trigger_in.power_fail.mask': expected a non-zero bit "
                               "mask in [0x1, 0xff], found 256");
  text = Replace(kConfig, "mask = 0x01\nvalue = 1", "mask = 0x01");
  EXPECT_THAT(ErrorOf(text), HasSubstr("missing key 'can.trigger_in.power_fail.value': expected "
                                       "an unsigned raw value in [0x0, 0xff]"));
  EXPECT_THAT(ErrorOf(Replace(kConfig, "[can.trigger_in.power_fail]", "[can.trigger_in.fail]")),
              HasSubstr("unknown key 'can.trigger_in.fail' (allowed here: power_fail, "
                        "power_restore)"));
}

TEST(CanConfigErrors, FrameLevelRules) {
  // Outgoing signals may not share bytes.
  std::string text =
      Replace(kConfig, "byte_offset = 2", "byte_offset = 1", "[can.sensors_out.s_de.y]");
  EXPECT_EQ(ErrorOf(text), At(text, "[can.sensors_out.s_de.y]") +
                               "signal 'can.sensors_out.s_de.y': bytes 1..2 of id 0x200 overlap "
                               "signal 'can.sensors_out.s_de.x' (" +
                               Loc(text, "[can.sensors_out.s_de.x]") + ", bytes 0..1 of id 0x200)");
  // Nor incoming currents.
  text = Replace(kConfig, "byte_offset = 2", "byte_offset = 1", "[can.currents_in.de.y]");
  EXPECT_THAT(ErrorOf(text), HasSubstr("signal 'can.currents_in.de.y': bytes 1..2 of id 0x100 "
                                       "overlap signal 'can.currents_in.de.x'"));
  // An id carries one direction.
  text = Replace(kConfig, "id = 0x210", "id = 0x100");
  EXPECT_EQ(ErrorOf(text), At(text, "[can.status_out.power_on]") +
                               "signal 'can.status_out.power_on': id 0x100 is sent by the "
                               "emulator and also received (signal 'can.currents_in.de.x', " +
                               Loc(text, "[can.currents_in.de.x]") +
                               "): an id carries one direction only");
  // A named table without axes.
  text = std::string(kConfig) + "\n[can.sensors_out.s_mid]\n";
  EXPECT_EQ(ErrorOf(text), At(text, "[can.sensors_out.s_mid]") +
                               "key 'can.sensors_out.s_mid': expected [can.sensors_out.s_mid.x] "
                               "and/or [can.sensors_out.s_mid.y]");
}

TEST(CanConfigErrors, NamesMustBeTheModels) {
  const CanNames names{.ambs = {"de", "mid"}, .sensors = {"s_de", "s_nde"}};
  EXPECT_THAT(ErrorOf(std::string(kConfig), &names),
              HasSubstr("key 'can.currents_in.nde': expected the name of an AMB of the model "
                        "(de, mid), found \"nde\""));
  EXPECT_THAT(ErrorOf(std::string(kConfig), &names), StartsWith("test.toml:"));
  const CanNames no_sensors{.ambs = {"de", "nde"}, .sensors = {}};
  EXPECT_THAT(ErrorOf(std::string(kConfig), &no_sensors),
              HasSubstr("key 'can.sensors_out.s_de': expected the name of a sensor of the model "
                        "(there are none), found \"s_de\""));
}

TEST(CanConfigErrors, BusSettings) {
  std::string text = Replace(kConfig, "exchange_rate_Hz = 1000", "exchange_rate_Hz = 5000");
  EXPECT_THAT(ErrorOf(text),
              StartsWith(At(text, "exchange_rate_Hz") +
                         "key 'can.exchange_rate_Hz': expected a rate the bus can carry: 7 "
                         "frames per exchange take up to "));
  EXPECT_THAT(ErrorOf(text), HasSubstr("at 1000000 bit/s, so at most 1"));
  EXPECT_THAT(ErrorOf(text), HasSubstr(" Hz, found 5000"));
  text = Replace(kConfig, "exchange_rate_Hz = 1000", "exchange_rate_Hz = 0");
  EXPECT_EQ(ErrorOf(text), At(text, "exchange_rate_Hz") +
                               "key 'can.exchange_rate_Hz': expected a positive number (Hz), "
                               "found 0");
  text = Replace(kConfig, "interface = \"vcan0\"\n", "");
  EXPECT_EQ(ErrorOf(text), "test.toml:1: missing key 'can.interface': expected a string");
  text = Replace(kConfig, "interface = \"vcan0\"", "interface = \"a_very_long_name0\"");
  EXPECT_THAT(ErrorOf(text), HasSubstr("key 'can.interface': expected an interface name of 1 to "
                                       "15 characters, found \"a_very_long_name0\""));
  text = Replace(kConfig, "exchange_rate_Hz = 1000",
                 "exchange_rate_Hz = 1000\nbit_rate_switch = true");
  EXPECT_EQ(ErrorOf(text), At(text, "bit_rate_switch") +
                               "key 'can.bit_rate_switch': expected no bit_rate_switch with fd = "
                               "false (classic CAN has none), found true");
  text = Replace(kConfig, "exchange_rate_Hz = 1000", "exchange_rate_Hz = 1000\nbitrate_bps = 2e6");
  EXPECT_THAT(ErrorOf(text), HasSubstr("key 'can.bitrate_bps': expected a number in (0, 1e6] "
                                       "(bit/s), found 2000000"));
  text = Replace(kConfig, "exchange_rate_Hz = 1000", "exchange_rate_Hz = 1000\ntx_len_bytes = 9");
  EXPECT_EQ(ErrorOf(text), At(text, "tx_len_bytes") +
                               "key 'can.tx_len_bytes': expected an integer in [0, 8], found 9");
  text = Replace(kConfig, "exchange_rate_Hz = 1000",
                 "exchange_rate_Hz = 1000\nfd = true\ntx_len_bytes = 13");
  EXPECT_EQ(ErrorOf(text), At(text, "tx_len_bytes") +
                               "key 'can.tx_len_bytes': expected a CAN FD length: 0..8, 12, 16, "
                               "20, 24, 32, 48 or 64, found 13");
  text = Replace(kConfig, "exchange_rate_Hz = 1000", "exchange_rate_Hz = 1000\ntx_len_bytes = 2");
  EXPECT_THAT(ErrorOf(text), HasSubstr("signal 'can.sensors_out.s_de.y': bytes 2..3 do not fit "
                                       "the sent length tx_len_bytes = 2"));
}

TEST(CanConfigErrors, DocumentLevel) {
  EXPECT_EQ(ErrorOf("[simulation]\nstep_s = 1e-5\n"),
            "test.toml:1: missing key 'can': expected a table ([can])");
  EXPECT_THAT(ErrorOf("[can]\ninterface = \"vcan0\nexchange_rate_Hz = 1\n"),
              StartsWith("test.toml:2: "));
}

}  // namespace
}  // namespace ambdrop::can_frame_map_test
