// SPDX-License-Identifier: MIT
// Scan manifests and their images: what the device writes is what the offline tools read, and
// every malformed manifest is refused in one line naming the key.
#include "vpe/proto/scan_manifest.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "vpe/proto/pnm_image.h"

#include "manifest_refusal.h"

namespace vpe::proto {
namespace {

ScanManifest smallManifest() {
    ScanManifest m;
    m.patterns = {64, 48, 8, 3};
    m.camera = {80, 60, 10, 20000, 2.0, "simulated:test"};
    m.createdBy = "test";
    m.projectorLatencyMs = 120;
    const StructuredLightSequence sequence(m.patterns);
    for (std::size_t i = 0; i < sequence.patterns().size(); ++i) {
        m.images.push_back({std::to_string(i) + "-" + sequence.patterns()[i].name() + ".pgm",
                            sequence.patterns()[i].name(), i == 3 ? 2 : 1});
    }
    return m;
}

std::string errorOf(const std::string& json) {
    return testing::refusalOf(parseScanManifest, json, "scan.json");
}

// Each text refused with exactly its one line.
void expectRefusals(const std::vector<std::pair<std::string, std::string>>& refusals) {
    for (const auto& [text, refusal] : refusals) {
        EXPECT_EQ(errorOf(text), refusal) << text;
    }
}

using testing::replaced;

TEST(ScanManifest, RoundTripsThroughJson) {
    const ScanManifest m = smallManifest();
    const ScanManifest back = parseScanManifest(scanManifestJson(m), "scan.json");
    EXPECT_EQ(back.patterns.width, 64);
    EXPECT_EQ(back.patterns.phasePeriod, 8);
    EXPECT_EQ(back.camera.bits, 10);
    EXPECT_EQ(back.camera.exposureUs, 20000);
    EXPECT_EQ(back.camera.source, "simulated:test");
    EXPECT_EQ(back.projectorLatencyMs, 120);
    ASSERT_EQ(back.images.size(), m.images.size());
    EXPECT_EQ(back.images[3].attempts, 2);
    EXPECT_EQ(back.images[5].file, m.images[5].file);
}

TEST(ScanManifest, RefusesEachMalformedManifestNamingTheKey) {
    const std::string good = scanManifestJson(smallManifest());
    expectRefusals({
        {good, ""},
        {"{",
         "scan.json: not JSON (parse error at line 1, column 2: syntax error "
         "while parsing object key - unexpected end of input; expected string "
         "literal)"},
        // A number beyond a double's range (found by the fuzzer).
        {replaced(good, "\"latency_ms\": 120", "\"latency_ms\": 1e30848"),
         "scan.json: not JSON (number overflow parsing '1e30848')"},
        {replaced(good, "\"vpe-scan\"", "\"other\""), "scan.json: format: expected \"vpe-scan\""},
        {replaced(good, "\"version\": 1", "\"version\": 2"),
         "scan.json: version 2: this reader reads version 1"},
        {replaced(good, "\"bits\": 10", "\"bits\": 12"),
         "scan.json: camera: bits: 12 (8, 10 or 16)"},
        {replaced(good, "\"phase_period\": 8", "\"phase_period\": 12"),
         "scan.json: projector: phase period 12 is not a power of two in 8..1024"},
        {replaced(good, "\"file\":\"0-white.pgm\"", "\"file\":\"../white.pgm\""),
         "scan.json: images[0]: file: '../white.pgm' is not a file name inside the folder"},
        {replaced(good, "\"pattern\":\"black\"", "\"pattern\":\"white\""),
         "scan.json: images[1]: pattern 'white' again (images[0] shows it)"},
        // Bit 0 is not shown when the phase's period is 8 (the Gray code stops at bit 1).
        {replaced(good, "\"pattern\":\"gray-x-b1\"", "\"pattern\":\"gray-x-b0\""),
         "scan.json: images[10]: pattern 'gray-x-b0' is not one of the declared sequence's 28 "
         "patterns"},
        {replaced(good, "\"phase_steps\": 3", "\"phase_steps\": 2"),
         "scan.json: projector: phase steps 2 outside 3..64 (0: no phase images)"},
        {replaced(good, "\"phase_steps\": 3", "\"phase_steps\": 3, \"code_step\": 0"),
         "scan.json: projector: code_step: 0 outside 1..16384"},
        {replaced(good, "\"phase_steps\": 3", "\"phase_steps\": 3, \"code_step\": 2"),
         "scan.json: projector: Gray bins of 4 pixels (code step 2, lowest bit 1) are wider "
         "than a quarter of the phase period 8"},
        {replaced(good, "\"phase_steps\": 3", "\"phase_steps\": 3, \"lowest_gray_bit\": 6"),
         "scan.json: projector: lowest Gray bit 6 outside 0..5 (the bits of the shorter axis' "
         "code)"},
        {replaced(good, "\"phase_steps\": 3", "\"phase_steps\": 3, \"flat_fields\": 0"),
         "scan.json: projector: flat_fields: expected true or false"},
        // The sequence shrinks to what is declared: the images it no longer has are refused.
        {replaced(good, "\"phase_steps\": 3", "\"phase_steps\": 3, \"flat_fields\": false"),
         "scan.json: images[0]: pattern 'white' is not one of the declared sequence's 26 "
         "patterns"},
    });
    // A missing image names the first missing pattern; an extra one is refused.
    const std::string last = ",\n    {\"file\":\"27-phase-y-s2.pgm\",\"pattern\":\"phase-y-s2\"}";
    const std::string shorter = replaced(good, last, "");
    EXPECT_EQ(errorOf(shorter),
              "scan.json: images: 27 of the sequence's 28 patterns (the first missing is "
              "'phase-y-s2')");
    EXPECT_EQ(errorOf(replaced(good, last, last + ",\n    {\"file\":\"x.pgm\",\"pattern\":\"x\"}")),
              "scan.json: images[28]: pattern 'x' is not one of the declared sequence's 28 "
              "patterns");
    EXPECT_EQ(errorOf(replaced(good, last, last + last)),
              "scan.json: images[28]: pattern 'phase-y-s2' again (images[27] shows it)");
}

TEST(ScanManifest, TodaysManifestsKeepTheirKeysAndTheirMeaning) {
    const std::string json = scanManifestJson(smallManifest());
    for (const char* key : {"code_step", "lowest_gray_bit", "flat_fields"}) {
        EXPECT_EQ(json.find(key), std::string::npos) << key;
    }
    const ScanManifest back = parseScanManifest(json, "scan.json");
    EXPECT_EQ(back.patterns.codeStep, 1);
    EXPECT_FALSE(back.patterns.lowestGrayBit.has_value());
    EXPECT_TRUE(back.patterns.flatFields);
    const StructuredLightSequence sequence(back.patterns);
    EXPECT_EQ(sequence.lowestGrayBit(), 1);  // log2(8) − 2
    ASSERT_EQ(back.images.size(), sequence.patterns().size());
    for (std::size_t i = 0; i < back.images.size(); ++i) {
        EXPECT_EQ(back.images[i].pattern, sequence.patterns()[i].name());
    }
}

// procam-calibration's layout: column bits, each with its inverse, then row bits, then white
// and black; every bit down to 0, no phase, a code step apart from the size.
TEST(ScanManifest, ReadsAForeignSequenceInItsOwnOrder) {
    ScanManifest m;
    m.patterns.width = 1024;
    m.patterns.height = 768;
    m.patterns.phaseSteps = 0;
    m.patterns.codeStep = 2;
    m.camera = {1280, 1024, 8, 0, 1.0, "imported:procam-calibration"};
    const StructuredLightSequence sequence(m.patterns);
    std::vector<std::string> order;
    for (const PatternSpec& pattern : sequence.patterns()) {
        if (pattern.kind == PatternKind::kGray) {
            order.push_back(pattern.name());
        }
    }
    order.insert(order.end(), {"white", "black"});
    for (std::size_t i = 0; i < order.size(); ++i) {
        m.images.push_back({"graycode_" + std::to_string(i) + ".png", order[i], 1});
    }
    const std::string json = scanManifestJson(m);
    EXPECT_EQ(json.find("phase_period"), std::string::npos);
    const ScanManifest back = parseScanManifest(json, "scan.json");
    EXPECT_EQ(back.patterns.phaseSteps, 0);
    EXPECT_EQ(back.patterns.codeStep, 2);
    ASSERT_EQ(back.images.size(), 2u * (9 + 9) + 2);
    EXPECT_EQ(back.images.front().pattern, "gray-x-b8");
    EXPECT_EQ(back.images[36].pattern, "white");
    EXPECT_EQ(back.images.back().file, "graycode_37.png");
    // Without white and black, as declared.
    m.patterns.flatFields = false;
    m.images.resize(36);
    EXPECT_EQ(parseScanManifest(scanManifestJson(m), "scan.json").images.size(), 36u);
    // A declared depth: bits below it are not in the sequence.
    m.patterns.lowestGrayBit = 2;
    EXPECT_EQ(errorOf(scanManifestJson(m)),
              "scan.json: images[14]: pattern 'gray-x-b1' is not one of the declared sequence's "
              "28 patterns");
}

TEST(ScanManifest, WritesAndReadsAFolder) {
    const auto folder = std::filesystem::temp_directory_path() / "vpe-scan-manifest-test";
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    writeScanManifest(folder, smallManifest());
    EXPECT_EQ(readScanManifest(folder).images.size(), 28u);
    EXPECT_EQ(readScanManifest(folder / kScanManifestName).images.size(), 28u);
    EXPECT_EQ(scanFolderOf(folder / kScanManifestName), folder);
    try {
        readScanManifest(folder / "missing");
        FAIL();
    } catch (const ScanManifestError& error) {
        EXPECT_EQ(std::string(error.what()),
                  (folder / "missing").string() + ": cannot open the scan manifest (no such file)");
    }
    std::filesystem::remove_all(folder);
}

TEST(PnmImage, WritesEightAndTenBitGreyAndColour) {
    const auto folder = std::filesystem::temp_directory_path() / "vpe-pnm-test";
    std::filesystem::create_directories(folder);
    const std::vector<std::uint16_t> ten{0, 512, 1023, 7, 100, 1000};
    writePnmAtomically(folder / "ten.pgm", 3, 2, 1, 1023, ten);
    std::ifstream in(folder / "ten.pgm", std::ios::binary);
    std::stringstream bytes;
    bytes << in.rdbuf();
    const std::string text = bytes.str();
    ASSERT_EQ(text.substr(0, 12), std::string("P5\n3 2\n1023\n"));
    EXPECT_EQ(text.size(), 12u + 12u);
    EXPECT_EQ(static_cast<unsigned char>(text[12 + 2]), 512 >> 8);  // big-endian
    const std::vector<std::uint8_t> rgb(2 * 2 * 3, 200);
    writePnmAtomically(folder / "rgb.ppm", 2, 2, 3, rgb);
    EXPECT_EQ(std::filesystem::file_size(folder / "rgb.ppm"), 11u + 12u);
    EXPECT_THROW(writePnmAtomically(folder / "bad.pgm", 3, 2, 1, 255, ten), std::invalid_argument);
    EXPECT_THROW(writePnmAtomically(folder / "bad.pgm", 4, 2, 1, 1023, ten), std::invalid_argument);
    EXPECT_FALSE(std::filesystem::exists(folder / "bad.pgm"));
    EXPECT_THROW(writePnmAtomically(folder / "missing" / "x.pgm", 3, 2, 1, 1023, ten),
                 std::runtime_error);
    std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace vpe::proto
