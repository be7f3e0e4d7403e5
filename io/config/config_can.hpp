#pragma once
// The [can] table of a config: the bus and the frame map (io/can/can_frame_map.hpp), read strictly
// like the rest of the config (unknown keys, wrong types and out-of-range values are ConfigError
// naming file, line and key).
//
// Schema (SI units; names in brackets are yours):
//
//   [can]
//   interface = "vcan0"          # required: network interface (can0, vcan0, ...)
//   exchange_rate_Hz = 5000      # required: frames of each id per second, both directions
//   fd = false                   # CAN FD frames (payload up to 64 bytes)
//   bit_rate_switch = true       # FD only (default true): data phase at data_bitrate_bps
//   bitrate_bps = 1000000        # nominal bit rate, bit/s (default 1e6)
//   data_bitrate_bps = 5000000   # FD only: data-phase bit rate, bit/s (default bitrate_bps)
//   byte_order = "little"        # default byte order of every signal: "little" or "big"
//   tx_len_bytes = 8             # optional: payload length of every sent frame (classic 0..8,
//                                # FD a DLC length); default: the least that holds its signals
//   filter_input_ids = true      # kernel filters pass only the received ids (default true)
//
//   Every signal table has the layout keys
//     id = 0x100                 # required: 0..0x7FF, or 0..0x1FFFFFFF with extended = true
//     extended = false           # 29-bit identifier
//     byte_offset = 0            # required: first payload byte
//     width_bytes = 2            # required: 1, 2 or 4 (whole bytes)
//     signed = false             # two's complement
//     byte_order = "little"      # default: [can].byte_order
//   and, with physical = raw * scale + offset:
//
//   [can.currents_in.[amb].x]    # and .y: coil control current of AMB [amb], A
//   scale_A_per_count = 0.001    # required, non-zero
//   offset_A = 0.0
//
//   [can.sensors_out.[sensor].x] # and .y: displacement at sensor [sensor], m; for ADC counts,
//   scale_m_per_count = 1e-7     # scale = m per count and offset = displacement at raw 0
//   offset_m = 0.0
//
//   [can.trigger_in.power_fail]  # and power_restore (both optional): switch the AMB power
//   mask = 0x01                  # bits compared (default: the whole width); unsigned only
//   value = 1                    # required: masked raw value that means the event
//   # or: any_frame = true       # the frame's arrival is the event; only id and extended then
//
//   [can.status_out.power_on]         # 1 powered, 0 after the power failure
//   [can.status_out.in_contact]       # 1 while any touchdown bearing is in contact
//   [can.status_out.step_counter]     # step index, modulo 2^(8 width_bytes)
//   [can.status_out.overrun_counter]  # real-time loop overruns, modulo 2^(8 width_bytes)
//   [can.status_out.spin_speed]       # rotor spin speed, rad/s:
//   scale_rad_s_per_count = 0.1       #   required, non-zero
//   offset_rad_s = 0.0
//
// A worst-case bus load (bit stuffing included) above 100 % at exchange_rate_Hz is an error:
// classic CAN at 1 Mbit/s carries about 7 400 frames/s of 8 bytes.
#include <filesystem>
#include <string>
#include <vector>

#include "io/can/can_frame_map.hpp"
#include "io/can/socketcan_bus.hpp"
#include "rt_core/model_params.hpp"

namespace ambdrop {

namespace config_detail {
class TableReader;
}

/// The AMB and sensor names of the model, in its order (the index of CanCommand::current_A and
/// EmulatorOutputs::sensor_xy_m).
struct CanNames {
  std::vector<std::string> ambs;
  std::vector<std::string> sensors;
};

/// The names of a loaded model's AMBs and sensors.
CanNames CanNamesOf(const ModelParams& params);

/// A validated [can] table.
struct CanConfig {
  std::string interface;
  double exchange_rate_Hz = 0.0;
  bool fd = false;
  bool bit_rate_switch = false;
  double bitrate_bps = 1e6;       ///< nominal bit rate, bit/s
  double data_bitrate_bps = 1e6;  ///< FD data phase, bit/s
  bool filter_input_ids = true;
  /// Worst-case share of the bus used at exchange_rate_Hz (both directions), 0..1.
  double bus_load = 0.0;
  FrameMap frame_map;

  /// What to open the bus with: interface, FD, and the kernel filters (if filter_input_ids).
  SocketCanOptions SocketOptions() const;
};

/// Reads the [can] table `can` (a reader of that table, path "can"). With `names`, every AMB and
/// sensor named must be in them and takes their index; without, the names found are indexed in
/// sorted order (the order the model loader uses for [amb.*] and [sensor.*]).
CanConfig ReadCanConfig(const config_detail::TableReader& can, const CanNames* names = nullptr);

/// Reads [can] from a TOML document (other root tables are left to their own readers).
/// `source_name` stands in for the file name in messages.
CanConfig LoadCanConfigFromString(const std::string& text, const std::string& source_name,
                                  const CanNames* names = nullptr);

/// Same, from a file.
CanConfig LoadCanConfig(const std::filesystem::path& path, const CanNames* names = nullptr);

}  // namespace ambdrop
