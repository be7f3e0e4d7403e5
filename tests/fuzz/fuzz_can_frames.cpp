// CAN frames through the PID rig's [can] frame map (configs/jarroux2019_industrial_pid_can.toml)
// into the emulator's CanControllerLink, over the kernel-faithful double
// (io/can/can_bus_double.hpp): the input is a run of raw socket writes (first byte: a classic
// 16-byte or an FD 72-byte record, then its bytes). The double refuses what the kernel refuses; the
// link counts what the map cannot decode; a current taken must be finite.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <span>

#include "fuzz_support.hpp"
#include "io/can/can_bus_double.hpp"
#include "io/config/config_loader.hpp"
#include "tools/hil/can_controller_link.hpp"

namespace {

struct Bench {
  ambdrop::LoadedConfig config =
      ambdrop::LoadConfig(ambdrop::fuzz::ConfigPath("jarroux2019_industrial_pid_can.toml"));
  ambdrop::VirtualCanBus medium{true};
  std::unique_ptr<ambdrop::CanBusDouble> emulator;
  std::unique_ptr<ambdrop::CanBusDouble> injector;
  std::unique_ptr<ambdrop::CanControllerLink> link;
  Bench() {
    ambdrop::CanSocketOptions fd;
    fd.fd_frames = true;
    emulator = std::make_unique<ambdrop::CanBusDouble>(medium, config.can->SocketOptions().socket);
    injector = std::make_unique<ambdrop::CanBusDouble>(medium, fd);
    link = std::make_unique<ambdrop::CanControllerLink>(
        emulator.get(), &config.can->frame_map,
        ambdrop::CanLinkOptions{.controller_period_s = 1e-3,
                                .exchange_rate_Hz = config.can->exchange_rate_Hz,
                                .tdb_count = static_cast<int>(config.params.tdbs.size())});
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Bench bench;
  std::size_t at = 0;
  while (at < size) {
    const std::size_t length = (data[at] & 1) != 0 ? 72 : 16;
    ++at;
    std::uint8_t record[72] = {};
    const std::size_t take = std::min(length, size - at);
    std::copy_n(data + at, take, record);
    at += take;
    (void)bench.injector->WriteRecord(std::span<const std::uint8_t>(record, length));
  }
  (void)bench.link->WaitForFrames(std::chrono::nanoseconds(0));
  ambdrop::CurrentsMessage currents;
  if (bench.link->PollCurrents(&currents)) {
    for (const auto& amb : currents.current_A) {
      for (const double i : amb) {
        if (!std::isfinite(i)) std::abort();
      }
    }
  }
  ambdrop::PowerEvent event;
  while (bench.link->Poll(0.0, &event)) {
  }
  return 0;
}
