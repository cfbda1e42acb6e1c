// SPDX-License-Identifier: MIT
// acceptInstallCommands: a command from the bus, the display lent, runCapture, progress and
// images on the bus.
#include "vpe/firmware/scan/install_capture.h"

#include <memory>
#include <string>

#include "vpe/firmware/loop/show_clock.h"
#include "vpe/firmware/player/player_log.h"
#include "vpe/firmware/scan/install_images.h"
#include "vpe/firmware/scan/scan_run.h"
#include "vpe/proto/radiometry_capture.h"

namespace vpe::firmware {

namespace gles = renderer::gles;

namespace {

// At most this many progress messages a second (the first and the last always go).
constexpr std::int64_t kProgressIntervalNs = 250'000'000;

// The capture's folder: [scan] out, else "scan" beside the bundle.
std::filesystem::path scanOutOf(const BoardConfig& board, const PlayerOptions& options) {
    if (board.scan && board.scan->out) {
        return *board.scan->out;
    }
    return options.bundle.parent_path() / "scan";
}

// One capture on the lent display; every outcome is published, none escapes but a stop.
class InstallCapture {
public:
    InstallCapture(bus::LightBus& bus, const BoardConfig& board, const PlayerOptions& options,
                   const bus::InstallCommand& command)
        : bus_(bus), board_(board), options_(options), beginNs_(monotonicNowNs()) {
        progress_.action = command.action;
        progress_.requestedBy = command.node;
        const std::filesystem::path out = scanOutOf(board, options);
        progress_.out =
            (command.action == bus::InstallAction::kRadiometry ? out / proto::kRadiometryFolderName
                                                               : out)
                .string();
    }

    void run(DisplayLease& lease) {
        const CaptureKind kind = progress_.action == bus::InstallAction::kRadiometry
                                     ? CaptureKind::kRadiometry
                                     : CaptureKind::kScan;
        step("opening the camera", true);
        std::string stoppedBy;
        try {
            if (!board_.scan) {
                throw PlayerInputError(board_.source +
                                       ":scan: missing; this node has no [scan] section to "
                                       "capture with (boards/README.md)");
            }
            const std::filesystem::path out = scanOutOf(board_, options_);
            std::optional<ScanFolder> folder;
            if (kind == CaptureKind::kScan) {
                folder.emplace(out);
            } else {
                folder.emplace(out / proto::kRadiometryFolderName, proto::kRadiometryManifestName);
            }
            // The simulation traces its scene here (seconds): the bus is served before and after.
            const std::unique_ptr<ScanCamera> camera = openScanCamera(board_);
            if (const std::string why = lease.keepAlive(); !why.empty()) {
                throw ScanError("scan: stopped by " + why + "; nothing written");
            }
            // The patterns go through the player's own target when it has their size (KMS: always,
            // the display's mode); headless, a target of the simulated projector's size beside it.
            const std::array<int, 2> size =
                scanProjectorSize(lease.platform, options_, board_, *camera);
            std::unique_ptr<gles::RenderTarget> own;
            gles::RenderTarget* target = &lease.target;
            if (size[0] != lease.target.width() || size[1] != lease.target.height()) {
                try {
                    own = lease.platform.createRenderTarget(size[0], size[1]);
                } catch (const gles::GraphicsError& error) {
                    throw PlayerInputError(error.what());
                }
                target = own.get();
            }
            CaptureStage stage{*camera, *target, lease.platform.description(),
                               [&lease, &stoppedBy] {
                                   stoppedBy = lease.keepAlive();
                                   return stoppedBy;
                               }};
            CaptureObserver observer;
            observer.progress = [this](const CaptureProgress& progress) {
                progress_.framesDone = progress.done;
                progress_.framesTotal = progress.total;
                step(progress.step, false);
            };
            observer.cameraView = [this](const CameraImage& image) {
                bus_.publishInstallImage("camera", encodeGreyPng(cameraPreview(image)));
            };
            observer.coverage = [this](const CoverageMap& coverage) {
                progress_.litFraction = coverage.litFraction();
                if (coverage.hasGrayPairs()) {
                    progress_.decodableFraction = coverage.decodableFraction();
                }
                bus_.publishInstallImage("coverage", encodeGreyPng(coverage.image()));
            };
            step("showing black", true);
            const ScanReport report = runCapture(board_, kind, *folder, stage, observer);
            progress_.state = bus::InstallState::kDone;
            progress_.result = report.summaryLine();
            playerLog("install: " + progress_.result);
        } catch (const std::exception& error) {
            // Bad settings, a camera that is absent or in use, captures that kept failing, a
            // display error: one line, the show goes on.
            progress_.state = bus::InstallState::kFailed;
            progress_.error = error.what();
            playerLog(std::string("install: ") + installActionName(progress_.action) +
                      " failed: " + error.what());
        }
        step(progress_.state == bus::InstallState::kDone ? "done" : "failed", true);
    }

private:
    void step(const std::string& name, bool always) {
        progress_.step = name;
        const std::int64_t now = monotonicNowNs();
        const bool last =
            progress_.framesTotal > 0 && progress_.framesDone == progress_.framesTotal;
        if (!always && !last && now - lastPublishNs_ < kProgressIntervalNs) {
            return;
        }
        lastPublishNs_ = now;
        progress_.timeUs = realtimeNowNs() / 1000;
        progress_.elapsedS = static_cast<double>(now - beginNs_) * 1e-9;
        bus_.publishInstallProgress(progress_);
    }

    bus::LightBus& bus_;
    const BoardConfig& board_;
    const PlayerOptions& options_;
    std::int64_t beginNs_;
    std::int64_t lastPublishNs_ = 0;
    bus::InstallProgress progress_;
};

}  // namespace

void acceptInstallCommands(Player& player, bus::LightBus& bus, const BoardConfig& board,
                           const PlayerOptions& options) {
    bus::LightBus* commands = &bus;
    Player* lender = &player;
    bus.onInstallCommand([commands, lender, &board, &options](const bus::InstallCommand& command) {
        auto capture = std::make_shared<InstallCapture>(*commands, board, options, command);
        if (!lender->lendDisplay([capture](DisplayLease& lease) { capture->run(lease); })) {
            playerLog(std::string("install: ") + installActionName(command.action) +
                      " asked by \"" + command.node.substr(0, 64) +
                      "\" refused: a capture is already running on this node");
        }
    });
}

}  // namespace vpe::firmware
