#pragma once
// LCM's event-log file format (what lcm-logger writes and lcm-logplayer / lcm-spy read): a
// sequence of events, each
//   uint32 sync 0xEDA1DA01 | int64 event number | int64 timestamp (us) | int32 channel length |
//   int32 data length | channel bytes | data bytes          (all integers big-endian).
// The writer and the reader are ours rather than liblcm's lcm_eventlog_*: the reader must
// survive damaged files (bounded lengths, no allocation from a corrupt length) and say at which
// byte the damage starts, which liblcm's reader cannot.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace ambdrop {

inline constexpr std::uint32_t kEventLogSync = 0xEDA1DA01U;
inline constexpr std::int32_t kEventLogMaxChannel = 256;            ///< as LCM's channel limit
inline constexpr std::int32_t kEventLogMaxData = 64 * 1024 * 1024;  ///< sanity bound, bytes

struct LogEvent {
  std::int64_t number = 0;
  std::int64_t timestamp_us = 0;
  std::string channel;
  std::vector<std::uint8_t> data;
  std::int64_t offset = 0;  ///< byte offset of its sync word in the file
};

/// Appends events to a new file. Not real-time: called from a writer thread.
class EventLogWriter {
 public:
  /// Creates (truncates) `path`; throws std::runtime_error naming the path on failure.
  explicit EventLogWriter(const std::filesystem::path& path);
  ~EventLogWriter();
  EventLogWriter(const EventLogWriter&) = delete;
  EventLogWriter& operator=(const EventLogWriter&) = delete;

  /// Writes one event numbered events() (0, 1, ...). Throws on a write error.
  void Write(const std::string& channel, std::int64_t timestamp_us,
             std::span<const std::uint8_t> data);
  /// Flushes and closes; throws on a write error. Called by the destructor if needed (quietly).
  void Close();
  std::int64_t events() const noexcept { return events_; }
  std::int64_t bytes() const noexcept { return bytes_; }

 private:
  std::FILE* file_ = nullptr;
  std::filesystem::path path_;
  std::int64_t events_ = 0;
  std::int64_t bytes_ = 0;
};

enum class LogReadStatus { kEvent, kEnd, kTruncated, kCorrupt };

/// Reads events in order. A damaged file ends the reading with kTruncated (the file stops inside
/// an event) or kCorrupt (a wrong sync word or an impossible length) and a message saying where.
class EventLogReader {
 public:
  /// Throws std::runtime_error if the file cannot be opened.
  explicit EventLogReader(const std::filesystem::path& path);
  ~EventLogReader();
  EventLogReader(const EventLogReader&) = delete;
  EventLogReader& operator=(const EventLogReader&) = delete;

  LogReadStatus Next(LogEvent* event);
  /// What went wrong, with the byte offset (after kTruncated or kCorrupt).
  const std::string& problem() const noexcept { return problem_; }
  std::int64_t offset() const noexcept { return offset_; }  ///< bytes consumed so far
  std::int64_t file_size() const noexcept { return size_; }

 private:
  std::FILE* file_ = nullptr;
  std::int64_t offset_ = 0;
  std::int64_t size_ = 0;
  std::string problem_;
};

/// FNV-1a 64-bit hash, continued from `hash` (start with kFnv1a64Basis).
inline constexpr std::uint64_t kFnv1a64Basis = 14695981039346656037ULL;
constexpr std::uint64_t Fnv1a64(std::span<const std::uint8_t> bytes,
                                std::uint64_t hash = kFnv1a64Basis) noexcept {
  for (const std::uint8_t b : bytes) {
    hash ^= b;
    hash *= 1099511628211ULL;
  }
  return hash;
}
/// The same over a string's bytes.
std::uint64_t Fnv1a64(const std::string& text, std::uint64_t hash = kFnv1a64Basis) noexcept;

}  // namespace ambdrop
