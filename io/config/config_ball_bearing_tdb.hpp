#pragma once
// Reader of [tdb.NAME.ball_bearing_tdb], the seed-002 TDB (Chen 2019): see
// rt_core/ball_bearing_tdb_params.hpp for the meaning of each key.
#include "io/config/toml_reader.hpp"
#include "rt_core/model_params.hpp"

namespace ambdrop::config_detail {

/// Reads and checks [tdb.NAME.ball_bearing_tdb]; the races' gravity comes from [gravity].
BallBearingTdbParams ReadBallBearingTdb(const TableReader& tdb, const GravityParams& gravity);

}  // namespace ambdrop::config_detail
