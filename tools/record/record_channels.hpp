#pragma once
// Channel names of a run record (an LCM event log). The sensor and state channels carry the
// same types, under the same names, as the live LCM link, so lcm-spy shows a record as it shows
// a live run.

namespace ambdrop {

inline constexpr const char* kRecHeaderChannel = "AMBDROP_RECORD_HEADER";
inline constexpr const char* kRecStartChannel = "AMBDROP_REC_START";
inline constexpr const char* kRecInputChannel = "AMBDROP_REC_INPUT";
inline constexpr const char* kRecPowerChannel = "AMBDROP_REC_POWER";
inline constexpr const char* kRecSensorsChannel = "AMBDROP_SENSORS";
inline constexpr const char* kRecStateChannel = "AMBDROP_STATE";
inline constexpr const char* kRecCheckChannel = "AMBDROP_REC_CHECK";
inline constexpr const char* kRecFooterChannel = "AMBDROP_RECORD_FOOTER";

}  // namespace ambdrop
