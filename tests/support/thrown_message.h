// SPDX-License-Identifier: MIT
// The refusal tests' reading of an error: the message of the exception a call throws, so that a
// test compares whole one-line messages. Header-only and dependency-free: the device-only
// build's tests include it too.
#pragma once

#include <string>

namespace vpe::testing {

// The what() of the Error that action throws; `none` when it throws nothing.
template <typename Error, typename Action>
std::string thrownMessage(Action&& action, const std::string& none = "(no error)") {
    try {
        action();
    } catch (const Error& error) {
        return error.what();
    }
    return none;
}

}  // namespace vpe::testing
