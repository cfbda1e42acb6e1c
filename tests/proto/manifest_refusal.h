// SPDX-License-Identifier: MIT
// The manifests' refusal tests (scan.json, radiometry.json): the one line a parser refuses a
// manifest with, and a good manifest's text with one value changed.
#pragma once

#include <string>

#include <gtest/gtest.h>

#include "vpe/proto/scan_manifest.h"

namespace vpe::proto::testing {

// The ScanManifestError parse(json, source) throws; "" when it reads the manifest.
template <typename Parse>
std::string refusalOf(Parse&& parse, const std::string& json, const std::string& source) {
    try {
        parse(json, source);
    } catch (const ScanManifestError& error) {
        return error.what();
    }
    return "";
}

// text with its first `from` replaced by `to`; a failure, and text unchanged, when there is
// none (the test's edit missed).
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

}  // namespace vpe::proto::testing
