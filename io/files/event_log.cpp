#include "io/files/event_log.hpp"

#include <array>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace ambdrop {
namespace {

constexpr std::size_t kHeaderBytes = 4 + 8 + 8 + 4 + 4;

void PutBigEndian(std::uint64_t value, int bytes, std::uint8_t* out) {
  for (int i = bytes - 1; i >= 0; --i) {
    out[i] = static_cast<std::uint8_t>(value & 0xFFU);
    value >>= 8;
  }
}

std::uint64_t GetBigEndian(const std::uint8_t* in, int bytes) {
  std::uint64_t value = 0;
  for (int i = 0; i < bytes; ++i) value = (value << 8) | in[i];
  return value;
}

std::string Where(std::int64_t offset) {
  return "byte " + std::to_string(offset);
}

}  // namespace

std::uint64_t Fnv1a64(const std::string& text, std::uint64_t hash) noexcept {
  return Fnv1a64(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()),
                                               text.size()),
                 hash);
}

EventLogWriter::EventLogWriter(const std::filesystem::path& path) : path_(path) {
  file_ = std::fopen(path.c_str(), "wb");
  if (file_ == nullptr) {
    throw std::runtime_error(path.string() + ": cannot create: " + std::strerror(errno));
  }
}

EventLogWriter::~EventLogWriter() {
  if (file_ != nullptr) std::fclose(file_);
}

void EventLogWriter::Write(const std::string& channel, std::int64_t timestamp_us,
                           std::span<const std::uint8_t> data) {
  if (file_ == nullptr) throw std::logic_error("EventLogWriter: write after close");
  std::array<std::uint8_t, kHeaderBytes> header{};
  PutBigEndian(kEventLogSync, 4, &header[0]);
  PutBigEndian(static_cast<std::uint64_t>(events_), 8, &header[4]);
  PutBigEndian(static_cast<std::uint64_t>(timestamp_us), 8, &header[12]);
  PutBigEndian(channel.size(), 4, &header[20]);
  PutBigEndian(data.size(), 4, &header[24]);
  if (std::fwrite(header.data(), 1, header.size(), file_) != header.size() ||
      std::fwrite(channel.data(), 1, channel.size(), file_) != channel.size() ||
      std::fwrite(data.data(), 1, data.size(), file_) != data.size()) {
    throw std::runtime_error(path_.string() + ": write failed: " + std::strerror(errno));
  }
  ++events_;
  bytes_ += static_cast<std::int64_t>(header.size() + channel.size() + data.size());
}

void EventLogWriter::Close() {
  if (file_ == nullptr) return;
  const bool ok = std::fflush(file_) == 0;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!ok || !closed) {
    throw std::runtime_error(path_.string() + ": close failed: " + std::strerror(errno));
  }
}

EventLogReader::EventLogReader(const std::filesystem::path& path) {
  file_ = std::fopen(path.c_str(), "rb");
  if (file_ == nullptr) {
    throw std::runtime_error(path.string() + ": cannot open: " + std::strerror(errno));
  }
  std::error_code ec;
  size_ = static_cast<std::int64_t>(std::filesystem::file_size(path, ec));
}

EventLogReader::~EventLogReader() {
  if (file_ != nullptr) std::fclose(file_);
}

LogReadStatus EventLogReader::Next(LogEvent* event) {
  if (!problem_.empty()) return LogReadStatus::kCorrupt;
  std::array<std::uint8_t, kHeaderBytes> header{};
  const std::size_t got = std::fread(header.data(), 1, header.size(), file_);
  if (got == 0) return LogReadStatus::kEnd;
  const std::int64_t start = offset_;
  if (got < header.size()) {
    problem_ = "the log ends inside an event header at " + Where(start + got) +
               " (event starting at " + Where(start) + ")";
    return LogReadStatus::kTruncated;
  }
  if (GetBigEndian(&header[0], 4) != kEventLogSync) {
    problem_ = "no event sync word at " + Where(start) + ": the log is corrupt from there";
    return LogReadStatus::kCorrupt;
  }
  const auto channel_len = static_cast<std::int32_t>(GetBigEndian(&header[20], 4));
  const auto data_len = static_cast<std::int32_t>(GetBigEndian(&header[24], 4));
  if (channel_len <= 0 || channel_len > kEventLogMaxChannel || data_len < 0 ||
      data_len > kEventLogMaxData) {
    problem_ = "impossible channel or data length (" + std::to_string(channel_len) + ", " +
               std::to_string(data_len) + ") in the event at " + Where(start);
    return LogReadStatus::kCorrupt;
  }
  event->offset = start;
  event->number = static_cast<std::int64_t>(GetBigEndian(&header[4], 8));
  event->timestamp_us = static_cast<std::int64_t>(GetBigEndian(&header[12], 8));
  event->channel.resize(static_cast<std::size_t>(channel_len));
  event->data.resize(static_cast<std::size_t>(data_len));
  const std::size_t body = static_cast<std::size_t>(channel_len) + data_len;
  std::size_t read = std::fread(event->channel.data(), 1, event->channel.size(), file_);
  if (read == event->channel.size() && data_len > 0) {
    read += std::fread(event->data.data(), 1, event->data.size(), file_);
  }
  if (read < body) {
    problem_ = "the log ends inside the event at " + Where(start) + " (" +
               std::to_string(body - read) + " of its bytes missing)";
    return LogReadStatus::kTruncated;
  }
  offset_ = start + static_cast<std::int64_t>(header.size() + body);
  return LogReadStatus::kEvent;
}

}  // namespace ambdrop
