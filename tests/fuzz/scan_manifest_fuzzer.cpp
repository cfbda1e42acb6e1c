// SPDX-License-Identifier: MIT
// libFuzzer target: arbitrary bytes as a scan.json either parse into a manifest whose images are
// exactly the sequence's patterns (each once, in any order), or fail with a ScanManifestError
// naming the file; anything else (a crash, another exception, an accepted manifest that breaks that
// promise) aborts.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <set>
#include <string>
#include <string_view>

#include "vpe/proto/scan_manifest.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const vpe::proto::ScanManifest manifest =
            vpe::proto::parseScanManifest(text, "fuzz/scan.json");
        // What the decoder relies on once a manifest is accepted.
        const vpe::proto::StructuredLightSequence sequence(manifest.patterns);
        if (manifest.images.size() != sequence.patterns().size() ||
            (manifest.camera.bits != 8 && manifest.camera.bits != 10 &&
             manifest.camera.bits != 16) ||
            manifest.camera.width < 1 || manifest.camera.height < 1) {
            std::abort();
        }
        std::set<std::string> shown;
        for (const vpe::proto::ScanImage& image : manifest.images) {
            if (sequence.find(image.pattern) < 0 || !shown.insert(image.pattern).second ||
                image.file.empty() || image.file.find('/') != std::string::npos ||
                image.attempts < 1) {
                std::abort();
            }
        }
    } catch (const vpe::proto::ScanManifestError& error) {
        if (!std::string_view(error.what()).starts_with("fuzz/scan.json: ")) {
            std::abort();
        }
    }
    return 0;
}
