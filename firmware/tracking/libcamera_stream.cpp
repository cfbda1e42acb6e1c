// SPDX-License-Identifier: MIT
// LibcameraStream: libcamera 0.0.3 in the order its `cam` tool uses — CameraManager start, pick
// and acquire the camera, generate/validate/configure, allocate and map the buffers, create
// the requests, start, queue — and undone in reverse. Completed requests come back on
// libcamera's thread; they are handed to the owner's thread through a mutex-protected list and
// an eventfd, so frames are read where they are used.
#include "vpe/firmware/tracking/libcamera_stream.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <span>
#include <utility>
#include <vector>

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

class LibcameraStream::Session {
public:
    Session() = default;
    ~Session();
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

    // Opens and starts the camera; throws CameraUnavailable. On a throw the destructor undoes
    // whatever was done.
    void open(const CameraStreamSettings& settings);
    void drain(const std::function<void(const CameraFrameView&)>& onFrame, bool newestOnly);

    int eventFd_ = -1;
    std::string name_;  // the camera's id
    std::string description_;
    int width_ = 0;
    int height_ = 0;
    bool exposureFixed_ = false;

private:
    struct Mapping {
        void* base = nullptr;
        std::size_t length = 0;
        std::span<const std::uint8_t> luminance;  // the first plane
    };

    [[noreturn]] void fail(const std::string& problem) const;
    void pickCamera(const std::string& id);
    void configure(const CameraStreamSettings& settings);
    void mapBuffers();
    void createRequests();
    void setControls(libcamera::ControlList& controls, const CameraStreamSettings& settings);
    // libcamera's thread.
    void requestComplete(libcamera::Request* request);

    std::unique_ptr<libcamera::CameraManager> manager_;
    bool managerStarted_ = false;
    std::shared_ptr<libcamera::Camera> camera_;
    bool acquired_ = false;
    bool connected_ = false;
    bool started_ = false;
    std::unique_ptr<libcamera::CameraConfiguration> configuration_;
    libcamera::Stream* stream_ = nullptr;
    int stride_ = 0;
    std::unique_ptr<libcamera::FrameBufferAllocator> allocator_;
    std::map<const libcamera::FrameBuffer*, Mapping> mappings_;
    std::vector<std::unique_ptr<libcamera::Request>> requests_;

    std::mutex mutex_;
    std::vector<libcamera::Request*> completed_;  // guarded by mutex_
};

LibcameraStream::Session::~Session() {
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

void LibcameraStream::Session::fail(const std::string& problem) const {
    throw CameraUnavailable("camera " + name_ + ": " + problem);
}

void LibcameraStream::Session::open(const CameraStreamSettings& settings) {
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
    pickCamera(settings.id);
    if (const int result = camera_->acquire(); result != 0) {
        fail("cannot acquire it (" + errorText(result) + "; is another program using it?)");
    }
    acquired_ = true;
    configure(settings);
    mapBuffers();
    createRequests();

    camera_->requestCompleted.connect(this, &Session::requestComplete);
    connected_ = true;
    libcamera::ControlList controls(camera_->controls());
    setControls(controls, settings);
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

void LibcameraStream::Session::pickCamera(const std::string& id) {
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

void LibcameraStream::Session::configure(const CameraStreamSettings& settings) {
    const bool still = settings.role == CameraStreamRole::kStillCapture;
    configuration_ = camera_->generateConfiguration(
        {still ? libcamera::StreamRole::StillCapture : libcamera::StreamRole::Viewfinder});
    if (!configuration_ || configuration_->empty()) {
        fail(still ? "offers no still capture stream" : "offers no viewfinder stream");
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
    stream.size = libcamera::Size(static_cast<unsigned int>(settings.width),
                                  static_cast<unsigned int>(settings.height));
    // A still stream may come with a single buffer: the camera would then idle while the one
    // frame is being read.
    stream.bufferCount = std::max(stream.bufferCount, settings.minBuffers);
    if (configuration_->validate() == libcamera::CameraConfiguration::Invalid) {
        fail("refuses the configuration " + stream.toString());
    }
    // validate() may adjust the size (the caller rescales or records it) but must keep a
    // luminance plane.
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
    exposureFixed_ = camera_->controls().count(&libcamera::controls::ExposureTime) != 0;
    description_ = "camera (" + model.value_or(name_) + " " + stream.toString();
    if (exposureFixed_) {
        description_ += ", exposure " + std::to_string(settings.exposureUs) + " us, gain " +
                        gainText(settings.analogueGain) + ")";
    } else {
        description_ += ", auto exposure: the camera has no ExposureTime control)";
    }
}

void LibcameraStream::Session::mapBuffers() {
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

void LibcameraStream::Session::createRequests() {
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

void LibcameraStream::Session::setControls(libcamera::ControlList& controls,
                                           const CameraStreamSettings& settings) {
    // Only controls the camera lists: libcamera logs an error for any other.
    const libcamera::ControlInfoMap& supported = camera_->controls();
    const auto lists = [&supported](const libcamera::ControlId& id) {
        return supported.count(&id) != 0;
    };
    if (lists(libcamera::controls::AeEnable)) {
        controls.set(libcamera::controls::AeEnable, false);
    }
    if (lists(libcamera::controls::ExposureTime)) {
        controls.set(libcamera::controls::ExposureTime,
                     static_cast<std::int32_t>(settings.exposureUs));
    }
    if (lists(libcamera::controls::AnalogueGain)) {
        controls.set(libcamera::controls::AnalogueGain, static_cast<float>(settings.analogueGain));
    }
    if (settings.fixedWhiteBalance && lists(libcamera::controls::AwbEnable)) {
        controls.set(libcamera::controls::AwbEnable, false);
    }
    if (settings.fixedWhiteBalance && settings.colourGains &&
        lists(libcamera::controls::ColourGains)) {
        const std::array<float, 2> gains{static_cast<float>((*settings.colourGains)[0]),
                                         static_cast<float>((*settings.colourGains)[1])};
        controls.set(libcamera::controls::ColourGains, libcamera::Span<const float, 2>(gains));
    }
    if (settings.frameDurationUs && lists(libcamera::controls::FrameDurationLimits)) {
        controls.set(libcamera::controls::FrameDurationLimits,
                     libcamera::Span<const std::int64_t, 2>(*settings.frameDurationUs));
    }
}

void LibcameraStream::Session::requestComplete(libcamera::Request* request) {
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

void LibcameraStream::Session::drain(const std::function<void(const CameraFrameView&)>& onFrame,
                                     bool newestOnly) {
    std::uint64_t count = 0;
    [[maybe_unused]] const ssize_t read = ::read(eventFd_, &count, sizeof count);
    std::vector<libcamera::Request*> completed;
    {
        const std::lock_guard lock(mutex_);
        completed.swap(completed_);
    }
    // Requests complete in capture order: the newest good frame is the last one.
    std::vector<libcamera::Request*> good;
    for (libcamera::Request* request : completed) {
        const libcamera::FrameBuffer* buffer = request->findBuffer(stream_);
        if (buffer != nullptr &&
            buffer->metadata().status == libcamera::FrameMetadata::FrameSuccess) {
            good.push_back(request);
        }
    }
    if (newestOnly && good.size() > 1) {
        good.erase(good.begin(), good.end() - 1);
    }
    for (libcamera::Request* request : good) {
        const libcamera::FrameBuffer* buffer = request->findBuffer(stream_);
        const Mapping& mapping = mappings_.at(buffer);
        CameraFrameView frame;
        frame.luminance = LuminanceView{width_, height_, stride_, mapping.luminance};
        // SensorTimestamp is the start of exposure (CLOCK_MONOTONIC); pipelines without it
        // leave the buffer's timestamp, the same clock.
        frame.timestampNs = request->metadata()
                                .get(libcamera::controls::SensorTimestamp)
                                .value_or(static_cast<std::int64_t>(buffer->metadata().timestamp));
        onFrame(frame);
    }
    for (libcamera::Request* request : completed) {
        request->reuse(libcamera::Request::ReuseBuffers);
        // A failure means the camera went away: frames stop, and the owner notices.
        camera_->queueRequest(request);
    }
}

LibcameraStream::LibcameraStream(const CameraStreamSettings& settings)
    : session_(std::make_unique<Session>()) {
    session_->open(settings);
}

LibcameraStream::~LibcameraStream() = default;

int LibcameraStream::eventFd() const {
    return session_->eventFd_;
}

const std::string& LibcameraStream::description() const {
    return session_->description_;
}

const std::string& LibcameraStream::cameraId() const {
    return session_->name_;
}

int LibcameraStream::width() const {
    return session_->width_;
}

int LibcameraStream::height() const {
    return session_->height_;
}

bool LibcameraStream::exposureFixed() const {
    return session_->exposureFixed_;
}

void LibcameraStream::drain(const std::function<void(const CameraFrameView&)>& onFrame,
                            bool newestOnly) {
    session_->drain(onFrame, newestOnly);
}

}  // namespace vpe::firmware
