#include "io/config/profile_config.hpp"

#include <fmt/format.h>

#include <toml++/toml.h>
#include <sstream>

#include "io/config/config_loader.hpp"

namespace ambdrop {
namespace {

toml::table& SubTable(toml::table& root, const std::string& key) {
  toml::table* t = root[key].as_table();
  if (t == nullptr) {
    root.insert_or_assign(key, toml::table{});
    t = root[key].as_table();
  }
  return *t;
}

}  // namespace

std::string ProfileConfigToml(const std::string& effective_toml, const ProfileConfig& profile) {
  toml::table root;
  try {
    root = toml::parse(effective_toml, std::string_view{"recorded config"});
  } catch (const toml::parse_error& e) {
    throw ConfigError(fmt::format("the recorded config does not parse: {}", e.description()));
  }
  root.insert_or_assign("name", profile.name);
  root.erase("scenario");
  root.insert_or_assign("controller", toml::table{{"kind", "none"}});

  toml::table& ambs = SubTable(root, "amb");
  for (std::size_t a = 0; a < profile.amb_names.size(); ++a) {
    const std::string& name = profile.amb_names[a];
    toml::table* amb = ambs[name].as_table();
    if (amb == nullptr) {
      throw ConfigError(fmt::format("the recorded config has no [amb.{}]", name));
    }
    const std::string law = amb->get("law") ? amb->get("law")->value_or(std::string{}) : "";
    if (law != "linearised_currents" && law != "electromagnet") {
      throw ConfigError(
          fmt::format("amb.{}: law = \"{}\" takes no coil currents; a current profile needs law = "
                      "\"linearised_currents\" or \"electromagnet\"",
                      name, law.empty() ? "equivalent" : law));
    }
    toml::array points;
    for (const CurrentSample& s : profile.ambs[a]) {
      points.push_back(toml::array{s.time_s, s.current_x_A, s.current_y_A});
    }
    amb->insert_or_assign("current_profile", std::move(points));
  }

  toml::table trigger{{"enabled", profile.trigger.enabled}};
  if (profile.trigger.enabled) {
    trigger.insert_or_assign("time_s", profile.trigger.time_s);
    if (profile.trigger.restore_time_s >= 0.0) {
      trigger.insert_or_assign("restore_time_s", profile.trigger.restore_time_s);
    }
    if (!profile.trigger.ambs.empty()) {
      toml::array names;
      for (const std::string& n : profile.trigger.ambs) names.push_back(n);
      trigger.insert_or_assign("ambs", std::move(names));
    }
    const bool x = profile.trigger.axis_x;
    const bool y = profile.trigger.axis_y;
    trigger.insert_or_assign("axes", x && y ? "xy" : (x ? "x" : "y"));
  }
  root.insert_or_assign("trigger", std::move(trigger));
  SubTable(root, "simulation").insert_or_assign("duration_s", profile.duration_s);

  std::ostringstream out;
  for (const std::string& line : profile.header_comments) out << "# " << line << '\n';
  out << '\n' << root << '\n';
  return out.str();
}

}  // namespace ambdrop
