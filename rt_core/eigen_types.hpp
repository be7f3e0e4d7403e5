#pragma once
#include <Eigen/Core>

#include "rt_core/limits.hpp"

namespace ambdrop {

/// Fixed-capacity, runtime-sized Eigen objects: they live inside their owner, never on the heap.
using ModalVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxModes, 1>;
using ModalMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxModes, kMaxModes>;
/// Maps generalized coordinates q to the lateral displacement (x, y) of one axial station.
using StationShape = Eigen::Matrix<double, 2, Eigen::Dynamic, 0, 2, kMaxModes>;
using StateVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxStateSize, 1>;

}  // namespace ambdrop
