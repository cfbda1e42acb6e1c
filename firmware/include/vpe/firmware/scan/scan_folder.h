// SPDX-License-Identifier: MIT
// ScanFolder: the scan is written into a hidden temporary folder beside OUT and moved into
// place only when every image passed its check and the manifest is written, so that OUT is
// either the previous scan or the new one, never half of one.
#pragma once

#include <filesystem>

namespace vpe::firmware {

class ScanFolder {
public:
    // Refuses (PlayerInputError, one line) an OUT that exists and is neither an empty folder nor
    // a folder of this kind (one holding `manifestName`: scan.json, or radiometry.json for a
    // radiometric capture alone, written into a scan folder's radiometry/; a scan folder may
    // also hold that folder alone): a capture never replaces anything else. Creates OUT's
    // parent when missing, and the temporary folder OUT/../.OUT.partial-PID.
    explicit ScanFolder(std::filesystem::path out, const char* manifestName = "scan.json");
    // Removes the temporary folder unless committed.
    ~ScanFolder();
    ScanFolder(const ScanFolder&) = delete;
    ScanFolder& operator=(const ScanFolder&) = delete;

    const std::filesystem::path& out() const { return out_; }
    const std::filesystem::path& temporary() const { return temporary_; }

    // Moves the temporary folder to OUT: renamed, or exchanged atomically with the previous
    // scan (renameat2 RENAME_EXCHANGE), which is then removed. Throws ScanError.
    void commit();

private:
    std::filesystem::path out_;
    std::filesystem::path temporary_;
    bool committed_ = false;
};

}  // namespace vpe::firmware
