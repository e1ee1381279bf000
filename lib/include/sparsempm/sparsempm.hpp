// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// \file sparsempm.hpp
/// Umbrella header: MPM operators as explicit sparse matrices.

#include "sparsempm/advance.hpp"
#include "sparsempm/boundary.hpp"
#include "sparsempm/contact.hpp"
#include "sparsempm/diagnostics.hpp"
#include "sparsempm/errors.hpp"
#include "sparsempm/fmpm.hpp"
#include "sparsempm/grid.hpp"
#include "sparsempm/loads.hpp"
#include "sparsempm/material.hpp"
#include "sparsempm/model.hpp"
#include "sparsempm/operators.hpp"
#include "sparsempm/particles.hpp"
#include "sparsempm/problems.hpp"
#include "sparsempm/scheme.hpp"
#include "sparsempm/shape.hpp"
#include "sparsempm/stages.hpp"
#include "sparsempm/step.hpp"
#include "sparsempm/step_options.hpp"
#include "sparsempm/step_preparation.hpp"
#include "sparsempm/transport.hpp"
#include "sparsempm/types.hpp"
#include "sparsempm/version.hpp"
