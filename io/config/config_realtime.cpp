#include "io/config/config_realtime.hpp"

#include "io/config/toml_reader.hpp"

namespace ambdrop {

RealtimeConfig ReadRealtimeConfig(const config_detail::TableReader& root) {
  RealtimeConfig c;
  const auto table = root.OptionalTable("realtime");
  if (!table) return c;
  table->AllowOnly({"priority", "cpu", "spin_s", "enforce"});
  c.priority = table->Integer("priority", 0, 99, c.priority);
  // CPU_SETSIZE (1024) bounds what the affinity call can name.
  c.cpu = table->Integer("cpu", -1, 1023, c.cpu);
  // Longer than 10 ms would be a busy loop, not a spin before a deadline.
  c.spin_s = table->Number("spin_s", config_detail::InRange(0.0, 0.01), c.spin_s);
  c.enforce = table->Bool("enforce", c.enforce);
  return c;
}

}  // namespace ambdrop
