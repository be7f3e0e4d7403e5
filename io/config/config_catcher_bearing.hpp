#pragma once
// Reader of [tdb.NAME.catcher_bearing], the seed-003 single/double-decker catcher bearing and the
// seed-004 metal rubber ring: see rt_core/catcher_bearing_params.hpp for each key's meaning.
#include "io/config/toml_reader.hpp"
#include "rt_core/model_params.hpp"

namespace ambdrop::config_detail {

/// Reads and checks [tdb.NAME.catcher_bearing]; the races' gravity comes from [gravity].
CatcherBearingParams ReadCatcherBearing(const TableReader& tdb, const GravityParams& gravity);

}  // namespace ambdrop::config_detail
