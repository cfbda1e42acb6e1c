// SPDX-License-Identifier: MIT
// ScanTest: vpe-player --scan run for real (PlayerTest's binary and folder) on the scan tests'
// installation (scan_installation.h), with what the tests read back: PGM and PPM images, the
// JSON report, folder listings.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "player_fixture.h"
#include "scan_installation.h"

namespace vpe::firmware::testing {

struct Pnm {
    int width = 0, height = 0, channels = 0, maxValue = 0;
    std::vector<std::uint16_t> samples;  // width·height·channels, interleaved
};

// Binary PGM or PPM as proto::writePnmAtomically writes it ("P5\nW H\nMAX\n" or "P6…",
// big-endian above 255); empty when it is neither.
inline Pnm readPnm(const fs::path& path) {
    const std::string bytes = readAll(path);
    Pnm pnm;
    std::size_t at = 0;
    const auto field = [&]() {
        const std::size_t end = bytes.find_first_of(" \n", at);
        const std::string text = bytes.substr(at, end - at);
        at = end + 1;
        return text;
    };
    const std::string magic = field();
    if (magic != "P5" && magic != "P6") {
        return pnm;
    }
    pnm.channels = magic == "P5" ? 1 : 3;
    pnm.width = std::stoi(field());
    pnm.height = std::stoi(field());
    pnm.maxValue = std::stoi(field());
    const std::size_t count = static_cast<std::size_t>(pnm.width) * pnm.height * pnm.channels;
    const std::size_t size = pnm.maxValue > 255 ? 2 : 1;
    if (bytes.size() != at + count * size) {
        return {};
    }
    pnm.samples.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + at + i * size);
        pnm.samples[i] = size == 2 ? static_cast<std::uint16_t>(p[0] << 8 | p[1]) : p[0];
    }
    return pnm;
}

// The JSON object that ends stdout.
inline nlohmann::json reportOf(const PlayerRun& run) {
    const std::size_t open = run.out.rfind("\n{");
    if (open == std::string::npos) {
        return {};
    }
    return nlohmann::json::parse(run.out.substr(open + 1), nullptr, false);
}

inline std::vector<std::string> namesIn(const fs::path& folder) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(folder)) {
        names.push_back(entry.path().filename().string());
    }
    std::sort(names.begin(), names.end());
    return names;
}

class ScanTest : public PlayerTest {
protected:
    void SetUp() override {
        PlayerTest::SetUp();
        installation_ = writeScanInstallation(folder_);
        out_ = folder_ / "scans" / "ball";
    }

    // A headless board simulating the installation's camera, with more [scan] keys.
    fs::path scanBoard(const std::string& scanKeys) {
        return writeFile("scan-board.toml",
                         "[display]\nbackend = \"headless\"\n[scan]\nsimulate = "
                         "\"installation.toml\"\n" +
                             scanKeys);
    }

    // Nothing in OUT's parent but what the test put there: no temporary folder left.
    void expectNoTemporaryFolders() {
        for (const std::string& name : namesIn(out_.parent_path())) {
            EXPECT_EQ(name.find(".partial-"), std::string::npos) << name;
            EXPECT_EQ(name.find(".previous-"), std::string::npos) << name;
        }
    }

    ScanInstallation installation_;
    fs::path out_;
};

}  // namespace vpe::firmware::testing
