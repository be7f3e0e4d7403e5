// LCM messages (io/lcm/lcm_types/*.lcm, decoded by lcm-gen's code and io/lcm/lcm_transport.cpp):
// the first byte picks a type; the rest is decoded as it. The controller's two inputs go the
// emulator's whole receive path: published on LCM's in-process memq:// provider and handled by
// the LcmEndpoint's own subscription (a malformed one is counted, a taken one must be finite
// and within its bound).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include <lcm/lcm-cpp.hpp>
#include "ambdrop_lcm/amb_currents_t.hpp"
#include "ambdrop_lcm/emulator_state_t.hpp"
#include "ambdrop_lcm/record_check_t.hpp"
#include "ambdrop_lcm/record_footer_t.hpp"
#include "ambdrop_lcm/record_header_t.hpp"
#include "ambdrop_lcm/record_start_t.hpp"
#include "ambdrop_lcm/recorded_input_t.hpp"
#include "ambdrop_lcm/recorded_power_t.hpp"
#include "ambdrop_lcm/sensor_readings_t.hpp"
#include "ambdrop_lcm/trigger_t.hpp"
#include "io/lcm/lcm_transport.hpp"
#include "tools/record/lcm_guarded_decode.hpp"

namespace {

template <typename Message>
void Decode(const std::uint8_t* data, std::size_t size) {
  Message msg;
  (void)msg.decode(data, 0, static_cast<int>(size));
}

// The types that carry strings (a record's header and footer) are decoded only through the
// run record reader's guard (tools/record/lcm_guarded_decode.hpp): lcm-gen's own decoder trusts
// a string's length.
template <typename Message>
void DecodeGuarded(const std::uint8_t* data, std::size_t size, int strings) {
  Message msg;
  (void)ambdrop::DecodeLcmGuarded(std::span<const std::uint8_t>(data, size), &msg, strings);
}

ambdrop::LcmEndpoint& Endpoint() {
  static ambdrop::LcmEndpoint endpoint([] {
    ambdrop::LcmEndpointOptions o;
    o.url = "memq://";
    o.current_bound_A.fill(20.0);
    return o;
  }());
  return endpoint;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0 || size > (1u << 20)) return 0;
  const std::uint8_t kind = data[0] % 12;
  ++data;
  --size;
  switch (kind) {
    case 0:
      Decode<ambdrop_lcm::amb_currents_t>(data, size);
      break;
    case 1:
      Decode<ambdrop_lcm::emulator_state_t>(data, size);
      break;
    case 2:
      Decode<ambdrop_lcm::record_check_t>(data, size);
      break;
    case 3:
      DecodeGuarded<ambdrop_lcm::record_footer_t>(data, size, ambdrop::kRecordFooterStrings);
      break;
    case 4:
      DecodeGuarded<ambdrop_lcm::record_header_t>(data, size, ambdrop::kRecordHeaderStrings);
      break;
    case 5:
      Decode<ambdrop_lcm::record_start_t>(data, size);
      break;
    case 6:
      Decode<ambdrop_lcm::recorded_input_t>(data, size);
      break;
    case 7:
      Decode<ambdrop_lcm::recorded_power_t>(data, size);
      break;
    case 8:
      Decode<ambdrop_lcm::sensor_readings_t>(data, size);
      break;
    case 9:
      Decode<ambdrop_lcm::trigger_t>(data, size);
      break;
    default: {
      ambdrop::LcmEndpoint& endpoint = Endpoint();
      const std::string& channel =
          kind == 10 ? endpoint.options().currents_channel : endpoint.options().trigger_channel;
      endpoint.lcm().publish(channel, data, static_cast<unsigned int>(size));
      while (endpoint.lcm().handleTimeout(0) > 0) {
      }
      ambdrop::HilCurrents currents;
      while (endpoint.TryPopCurrents(&currents)) {
        for (int a = 0; a < currents.amb_count; ++a) {
          for (const double i : currents.current_A[a]) {
            if (!std::isfinite(i) || std::abs(i) > 20.0) std::abort();
          }
        }
      }
      ambdrop::HilTrigger trigger;
      while (endpoint.TryPopTrigger(&trigger)) {
      }
    }
  }
  return 0;
}
