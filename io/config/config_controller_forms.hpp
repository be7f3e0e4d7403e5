#pragma once
// [controller.linear] (the general linear form) and [controller.amplifier].
#include "io/config/toml_reader.hpp"
#include "rt_core/controller_form_params.hpp"

namespace ambdrop::config_detail {

/// `rate_Hz` is the controller's sample rate (prewarp frequencies must lie below its Nyquist).
LinearControllerParams ReadLinearController(const TableReader& table, double rate_Hz);
AmplifierParams ReadAmplifier(const TableReader& table);

}  // namespace ambdrop::config_detail
