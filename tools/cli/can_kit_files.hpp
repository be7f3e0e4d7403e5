#pragma once
// The client kit's CAN files, generated from a config's [can] frame map (io/can/can_frame_map.hpp):
// a C header for firmware (one block of macros per signal, and inline helpers that read, write
// and scale raw values exactly as the frame map does) and a DBC file, the CAN world's format,
// for the usual CAN tools (SavvyCAN, cantools, Vector's). Both are generated, never edited: a
// change of the [can] table is a change of the files.
#include <string>

#include "io/can/can_frame_map.hpp"

namespace ambdrop {

/// The C header (C99, also valid C++). `source` names the config in its banner.
std::string CanFramesHeader(const FrameMap& map, double exchange_rate_Hz,
                            const std::string& source);

/// The DBC file: one message per frame id (BO_), one signal per signal of the map (SG_; the
/// power_fail and power_restore triggers that share their bytes as one signal with a value
/// table), nodes `ambdrop` (the emulator) and `controller`.
std::string CanFramesDbc(const FrameMap& map, const std::string& source);

/// The macro stem of a signal: its config path, upper-cased, with '_' for every other
/// character ("can.currents_in.de.x" -> "AMBDROP_CAN_CURRENTS_IN_DE_X").
std::string CanSignalMacro(const CanSignalSpec& signal);

}  // namespace ambdrop
