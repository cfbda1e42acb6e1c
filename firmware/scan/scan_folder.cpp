// SPDX-License-Identifier: MIT
// ScanFolder: a temporary folder beside OUT, renamed (or exchanged) into place.
#include "vpe/firmware/scan/scan_folder.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

#include "vpe/firmware/player/player.h"
#include "vpe/firmware/scan/scan_camera.h"
#include "vpe/proto/radiometry_capture.h"
#include "vpe/proto/scan_manifest.h"

namespace vpe::firmware {

namespace fs = std::filesystem;

namespace {

// A folder that holds nothing but a radiometric capture taken alone (radiometry/).
bool holdsRadiometryAlone(const fs::path& folder) {
    std::error_code error;
    fs::directory_iterator entries(folder, error);
    if (error) {
        return false;
    }
    for (const fs::directory_entry& entry : entries) {
        if (entry.path().filename() != proto::kRadiometryFolderName) {
            return false;
        }
    }
    return true;
}

}  // namespace

ScanFolder::ScanFolder(fs::path out, const char* manifestName) : out_(std::move(out)) {
    if (out_.filename().empty()) {
        out_ = out_.parent_path();  // "scans/x/" names the folder x
    }
    std::error_code error;
    const fs::file_status status = fs::symlink_status(out_, error);
    if (fs::exists(status)) {
        if (!fs::is_directory(status)) {
            throw PlayerInputError(out_.string() +
                                   ": exists and is not a folder; a scan writes a folder");
        }
        if (!fs::exists(out_ / manifestName) && !fs::is_empty(out_, error) &&
            !(std::string(manifestName) == proto::kScanManifestName &&
              holdsRadiometryAlone(out_))) {
            throw PlayerInputError(
                out_.string() + ": exists and is not a " +
                (std::string(manifestName) == proto::kScanManifestName ? "scan" : "radiometry") +
                " folder (no " + manifestName + "); refusing to replace it");
        }
    }
    const fs::path parent = out_.has_parent_path() ? out_.parent_path() : fs::path(".");
    fs::create_directories(parent, error);
    if (error || !fs::is_directory(parent)) {
        throw PlayerInputError(parent.string() + ": cannot create the folder for the scan (" +
                               (error ? error.message() : "not a folder") + ")");
    }
    // Hidden, on OUT's file system (so that the move is a rename), unique to this process.
    temporary_ =
        parent / ("." + out_.filename().string() + ".partial-" + std::to_string(::getpid()));
    fs::remove_all(temporary_, error);
    if (!fs::create_directory(temporary_, error) || error) {
        throw PlayerInputError(temporary_.string() +
                               ": cannot create the scan's temporary folder (" +
                               (error ? error.message() : "it exists") + ")");
    }
}

ScanFolder::~ScanFolder() {
    if (!committed_) {
        std::error_code ignored;
        fs::remove_all(temporary_, ignored);
    }
}

void ScanFolder::commit() {
    std::error_code error;
    if (!fs::exists(fs::symlink_status(out_, error))) {
        if (std::rename(temporary_.c_str(), out_.c_str()) != 0) {
            throw ScanError(out_.string() + ": cannot move the scan into place (" +
                            std::strerror(errno) + ")");
        }
        committed_ = true;
        return;
    }
    // The previous scan (or an empty folder) and the new one change places in one step; the
    // temporary name then holds the old one.
    if (::renameat2(AT_FDCWD, temporary_.c_str(), AT_FDCWD, out_.c_str(), RENAME_EXCHANGE) == 0) {
        committed_ = true;
        fs::remove_all(temporary_, error);
        return;
    }
    // A file system without the exchange: move the old one aside, then the new one in.
    const fs::path old = temporary_.parent_path() / ("." + out_.filename().string() + ".previous-" +
                                                     std::to_string(::getpid()));
    if (std::rename(out_.c_str(), old.c_str()) != 0) {
        throw ScanError(out_.string() + ": cannot move the previous scan aside (" +
                        std::strerror(errno) + ")");
    }
    if (std::rename(temporary_.c_str(), out_.c_str()) != 0) {
        const int saved = errno;
        std::rename(old.c_str(), out_.c_str());  // the previous scan back where it was
        throw ScanError(out_.string() + ": cannot move the scan into place (" +
                        std::strerror(saved) + ")");
    }
    committed_ = true;
    fs::remove_all(old, error);
}

}  // namespace vpe::firmware
