// SPDX-License-Identifier: MIT
// LibcameraLamp: libcamera 0.0.3 in the order its `cam` tool uses — CameraManager start, pick
// and acquire the camera, generate/validate/configure, allocate and map the buffers, create
// the requests, start, queue — and undone in reverse. Completed requests come back on
// libcamera's thread; they are handed to the player's thread through a mutex-protected list
// and an eventfd, so the tracker runs where the events are consumed.
#include "vpe/firmware/tracking/libcamera_lamp.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <span>
#include <utility>

#include <libcamera/camera.h>
#include <libcamera/camera_manager.h>
#include <libcamera/control_ids.h>
#include <libcamera/formats.h>
#include <libcamera/framebuffer.h>
#include <libcamera/framebuffer_allocator.h>
#include <libcamera/property_ids.h>
#include <libcamera/request.h>
#include <libcamera/stream.h>
#include <sys/eventfd.h>
#include <sys/mman.h>
#include <unistd.h>

namespace vpe::firmware {

namespace {

// Formats whose first plane is the 8-bit luminance, in order of preference (R8 carries nothing
// else; the YUV ones are what ISPs offer).
const std::array<libcamera::PixelFormat, 5> kLuminanceFirstFormats{
    libcamera::formats::R8, libcamera::formats::YUV420, libcamera::formats::NV12,
    libcamera::formats::NV21, libcamera::formats::YVU420};

bool isLuminanceFirst(const libcamera::PixelFormat& format) {
    return std::find(kLuminanceFirstFormats.begin(), kLuminanceFirstFormats.end(), format) !=
           kLuminanceFirstFormats.end();
}

// libcamera returns −errno.
std::string errorText(int result) {
    return std::strerror(result < 0 ? -result : result);
}

std::string gainText(double gain) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", gain);
    return text;
}

}  // namespace

class LibcameraLamp::Session {
public:
    Session() = default;
    ~Session();
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

    // Opens and starts the camera; throws CameraUnavailable. On a throw the destructor undoes
    // whatever was done.
    void open(const CameraConfig& config);

    int eventFd() const { return eventFd_; }
    const std::string& description() const { return description_; }

    // The player's thread: takes the completed requests, runs the tracker on the newest good
    // frame, queues them all again.
    void drain(LampTracker& tracker, std::vector<InputEvent>& events);

private:
    struct Mapping {
        void* base = nullptr;
        std::size_t length = 0;
        std::span<const std::uint8_t> luminance;  // the first plane
    };

    [[noreturn]] void fail(const std::string& problem) const;
    void pickCamera(const std::string& id);
    void configure(const CameraConfig& config);
    void mapBuffers();
    void createRequests();
    void setFixedExposure(libcamera::ControlList& controls, const CameraConfig& config);
    // libcamera's thread.
    void requestComplete(libcamera::Request* request);

    int eventFd_ = -1;
    std::unique_ptr<libcamera::CameraManager> manager_;
    bool managerStarted_ = false;
    std::shared_ptr<libcamera::Camera> camera_;
    std::string name_;  // for errors: the camera's id
    bool acquired_ = false;
    bool connected_ = false;
    bool started_ = false;
    std::unique_ptr<libcamera::CameraConfiguration> configuration_;
    libcamera::Stream* stream_ = nullptr;
    int width_ = 0;
    int height_ = 0;
    int stride_ = 0;
    std::unique_ptr<libcamera::FrameBufferAllocator> allocator_;
    std::map<const libcamera::FrameBuffer*, Mapping> mappings_;
    std::vector<std::unique_ptr<libcamera::Request>> requests_;
    std::string description_;

    std::mutex mutex_;
    std::vector<libcamera::Request*> completed_;  // guarded by mutex_
};

LibcameraLamp::Session::~Session() {
    if (started_) {
        // Blocks until the pipeline has completed (cancelled) every queued request.
        camera_->stop();
    }
    if (connected_) {
        camera_->requestCompleted.disconnect(this);
    }
    requests_.clear();
    for (const auto& [buffer, mapping] : mappings_) {
        ::munmap(mapping.base, mapping.length);
    }
    mappings_.clear();
    allocator_.reset();
    configuration_.reset();
    if (acquired_) {
        camera_->release();
    }
    camera_.reset();
    if (managerStarted_) {
        manager_->stop();
    }
    manager_.reset();
    if (eventFd_ >= 0) {
        ::close(eventFd_);
    }
}

void LibcameraLamp::Session::fail(const std::string& problem) const {
    throw CameraUnavailable("camera " + name_ + ": " + problem);
}

void LibcameraLamp::Session::open(const CameraConfig& config) {
    eventFd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    if (eventFd_ < 0) {
        throw CameraUnavailable(std::string("camera: cannot create an eventfd (") +
                                std::strerror(errno) + ")");
    }
    manager_ = std::make_unique<libcamera::CameraManager>();
    if (const int result = manager_->start(); result != 0) {
        throw CameraUnavailable("camera: libcamera's camera manager does not start (" +
                                errorText(result) + ")");
    }
    managerStarted_ = true;
    pickCamera(config.id);
    if (const int result = camera_->acquire(); result != 0) {
        fail("cannot acquire it (" + errorText(result) + "; is another program using it?)");
    }
    acquired_ = true;
    configure(config);
    mapBuffers();
    createRequests();

    camera_->requestCompleted.connect(this, &Session::requestComplete);
    connected_ = true;
    libcamera::ControlList controls(camera_->controls());
    setFixedExposure(controls, config);
    if (const int result = camera_->start(&controls); result != 0) {
        fail("cannot start streaming (" + errorText(result) + ")");
    }
    started_ = true;
    for (const std::unique_ptr<libcamera::Request>& request : requests_) {
        if (const int result = camera_->queueRequest(request.get()); result != 0) {
            fail("cannot queue a request (" + errorText(result) + ")");
        }
    }
}

void LibcameraLamp::Session::pickCamera(const std::string& id) {
    const std::vector<std::shared_ptr<libcamera::Camera>> cameras = manager_->cameras();
    std::string listed;
    for (const std::shared_ptr<libcamera::Camera>& camera : cameras) {
        listed += (listed.empty() ? "" : ", ") + camera->id();
    }
    listed = listed.empty() ? "libcamera lists none" : "libcamera lists: " + listed;
    if (id == "auto") {
        if (cameras.empty()) {
            throw CameraUnavailable("camera: no camera found (" + listed + ")");
        }
        camera_ = cameras.front();
    } else {
        camera_ = manager_->get(id);
        if (!camera_) {
            throw CameraUnavailable("camera: no camera \"" + id + "\" (" + listed + ")");
        }
    }
    name_ = camera_->id();
}

void LibcameraLamp::Session::configure(const CameraConfig& config) {
    configuration_ = camera_->generateConfiguration({libcamera::StreamRole::Viewfinder});
    if (!configuration_ || configuration_->empty()) {
        fail("offers no viewfinder stream");
    }
    libcamera::StreamConfiguration& stream = configuration_->at(0);
    const std::vector<libcamera::PixelFormat> offered = stream.formats().pixelformats();
    const auto preferred =
        std::find_if(kLuminanceFirstFormats.begin(), kLuminanceFirstFormats.end(),
                     [&offered](const libcamera::PixelFormat& format) {
                         return std::find(offered.begin(), offered.end(), format) != offered.end();
                     });
    if (preferred == kLuminanceFirstFormats.end()) {
        std::string list;
        for (const libcamera::PixelFormat& format : offered) {
            list += (list.empty() ? "" : ", ") + format.toString();
        }
        fail("offers no luminance-first format (R8, YUV420, NV12, NV21, YVU420), only " +
             (list.empty() ? std::string("none") : list));
    }
    stream.pixelFormat = *preferred;
    stream.size = libcamera::Size(static_cast<unsigned int>(config.tracking.width),
                                  static_cast<unsigned int>(config.tracking.height));
    if (configuration_->validate() == libcamera::CameraConfiguration::Invalid) {
        fail("refuses the configuration " + stream.toString());
    }
    // validate() may adjust the size (the tracker rescales) but must keep a luminance plane.
    if (!isLuminanceFirst(stream.pixelFormat)) {
        fail("adjusted the format to " + stream.pixelFormat.toString() +
             ", which has no luminance plane first");
    }
    if (const int result = camera_->configure(configuration_.get()); result != 0) {
        fail("refuses the configuration " + stream.toString() + " (" + errorText(result) + ")");
    }
    stream_ = stream.stream();
    width_ = static_cast<int>(stream.size.width);
    height_ = static_cast<int>(stream.size.height);
    stride_ = static_cast<int>(stream.stride);
    if (width_ <= 0 || height_ <= 0 || stride_ < width_) {
        fail("configured an unusable stream " + stream.toString());
    }

    const std::optional<std::string> model =
        camera_->properties().get(libcamera::properties::Model);
    description_ = "camera (" + model.value_or(name_) + " " + stream.toString();
    if (camera_->controls().count(&libcamera::controls::ExposureTime) != 0) {
        description_ += ", exposure " + std::to_string(config.exposureUs) + " us, gain " +
                        gainText(config.analogueGain) + ")";
    } else {
        description_ += ", auto exposure: the camera has no ExposureTime control)";
    }
}

void LibcameraLamp::Session::mapBuffers() {
    allocator_ = std::make_unique<libcamera::FrameBufferAllocator>(camera_);
    if (const int result = allocator_->allocate(stream_); result < 0) {
        fail("cannot allocate frame buffers (" + errorText(result) + ")");
    }
    const std::size_t needed =
        static_cast<std::size_t>(stride_) * static_cast<std::size_t>(height_ - 1) +
        static_cast<std::size_t>(width_);
    for (const std::unique_ptr<libcamera::FrameBuffer>& buffer : allocator_->buffers(stream_)) {
        const libcamera::FrameBuffer::Plane& plane = buffer->planes().front();
        if (plane.length < needed) {
            fail("gives a " + std::to_string(plane.length) + "-byte first plane, needs " +
                 std::to_string(needed));
        }
        // mmap offsets must be page-aligned and a plane's need not be: map from the start of
        // the dmabuf and point into it.
        const std::size_t length = static_cast<std::size_t>(plane.offset) + plane.length;
        void* base = ::mmap(nullptr, length, PROT_READ, MAP_SHARED, plane.fd.get(), 0);
        if (base == MAP_FAILED) {
            fail(std::string("cannot map a frame buffer (") + std::strerror(errno) + ")");
        }
        Mapping& mapping = mappings_[buffer.get()];
        mapping.base = base;
        mapping.length = length;
        mapping.luminance = {static_cast<const std::uint8_t*>(base) + plane.offset, plane.length};
    }
}

void LibcameraLamp::Session::createRequests() {
    for (const std::unique_ptr<libcamera::FrameBuffer>& buffer : allocator_->buffers(stream_)) {
        std::unique_ptr<libcamera::Request> request = camera_->createRequest();
        if (!request) {
            fail("cannot create a request");
        }
        if (const int result = request->addBuffer(stream_, buffer.get()); result != 0) {
            fail("cannot add a buffer to a request (" + errorText(result) + ")");
        }
        requests_.push_back(std::move(request));
    }
    if (requests_.empty()) {
        fail("allocated no frame buffers");
    }
}

void LibcameraLamp::Session::setFixedExposure(libcamera::ControlList& controls,
                                              const CameraConfig& config) {
    // Only controls the camera lists: libcamera logs an error for any other.
    const libcamera::ControlInfoMap& supported = camera_->controls();
    if (supported.count(&libcamera::controls::AeEnable) != 0) {
        controls.set(libcamera::controls::AeEnable, false);
    }
    if (supported.count(&libcamera::controls::ExposureTime) != 0) {
        controls.set(libcamera::controls::ExposureTime,
                     static_cast<std::int32_t>(config.exposureUs));
    }
    if (supported.count(&libcamera::controls::AnalogueGain) != 0) {
        controls.set(libcamera::controls::AnalogueGain, static_cast<float>(config.analogueGain));
    }
}

void LibcameraLamp::Session::requestComplete(libcamera::Request* request) {
    if (request->status() == libcamera::Request::RequestCancelled) {
        return;  // stopping: the request is not queued again
    }
    {
        const std::lock_guard lock(mutex_);
        completed_.push_back(request);
    }
    const std::uint64_t one = 1;
    // Fails only when the counter would overflow, and then the fd is readable anyway.
    [[maybe_unused]] const ssize_t written = ::write(eventFd_, &one, sizeof one);
}

void LibcameraLamp::Session::drain(LampTracker& tracker, std::vector<InputEvent>& events) {
    std::uint64_t count = 0;
    [[maybe_unused]] const ssize_t read = ::read(eventFd_, &count, sizeof count);
    std::vector<libcamera::Request*> completed;
    {
        const std::lock_guard lock(mutex_);
        completed.swap(completed_);
    }
    // Requests complete in capture order: the newest good frame is the last one.
    for (auto it = completed.rbegin(); it != completed.rend(); ++it) {
        const libcamera::FrameBuffer* buffer = (*it)->findBuffer(stream_);
        if (buffer == nullptr ||
            buffer->metadata().status != libcamera::FrameMetadata::FrameSuccess) {
            continue;
        }
        const Mapping& mapping = mappings_.at(buffer);
        const LuminanceView view{width_, height_, stride_, mapping.luminance};
        // SensorTimestamp is the start of exposure (CLOCK_MONOTONIC); pipelines without it
        // leave the buffer's timestamp, the same clock.
        const std::int64_t timestampNs =
            (*it)
                ->metadata()
                .get(libcamera::controls::SensorTimestamp)
                .value_or(static_cast<std::int64_t>(buffer->metadata().timestamp));
        tracker.onFrame(view, timestampNs, events);
        break;
    }
    for (libcamera::Request* request : completed) {
        request->reuse(libcamera::Request::ReuseBuffers);
        // A failure means the camera went away: frames stop and the tracker's hold runs out.
        camera_->queueRequest(request);
    }
}

LibcameraLamp::LibcameraLamp(const CameraConfig& config, LampDirectionMap map)
    : tracker_(config.tracking, std::move(map)), session_(std::make_unique<Session>()) {
    session_->open(config);
}

LibcameraLamp::LibcameraLamp(const CameraConfig& config)
    : LibcameraLamp(config, LampCalibration::fit(config.calibration)) {}

LibcameraLamp::~LibcameraLamp() = default;

std::string LibcameraLamp::description() const {
    return session_->description();
}

std::vector<int> LibcameraLamp::pollDescriptors() const {
    return {session_->eventFd()};
}

void LibcameraLamp::onReadable(int fd, std::int64_t /*nowNs*/, std::vector<InputEvent>& events) {
    if (fd == session_->eventFd()) {
        session_->drain(tracker_, events);
    }
}

void LibcameraLamp::onTick(std::int64_t nowNs, std::vector<InputEvent>& events) {
    tracker_.tick(nowNs, events);
}

}  // namespace vpe::firmware
