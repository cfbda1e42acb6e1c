// SPDX-License-Identifier: MIT
// InputError: bad input from the user (a file, a line of it, a value), reported in one line
// that names the input. The offline rooms' name for proto's one bad-input base: the `vpe`
// command turns it, and every error derived from it, into exit status 2.
#pragma once

#include "vpe/proto/input_error.h"

namespace vpe::common {

using InputError = proto::InputError;

}  // namespace vpe::common
