// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file version.hpp
namespace smpm {
/// Library version, "major.minor.patch".
inline constexpr const char* kVersion = "0.2.0";
} // namespace smpm
