// SPDX-License-Identifier: MIT
// LibcameraStream: libcamera 0.0.3 in the order its `cam` tool uses — CameraManager start, pick
// and acquire the camera, generate/validate/configure, allocate and map the buffers, create
// the requests, start, queue — and undone in reverse. Completed requests come back on
// libcamera's thread; they are handed to the owner's thread through a mutex-protected list and
// an eventfd, so frames are read where they are used. With colour asked for, a YUV 4:2:0 format
// comes first and every plane of the buffers is mapped.
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
#include <libcamera/color_space.h>
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

// The same with colour wanted: the YUV 4:2:0 ones first.
const std::array<libcamera::PixelFormat, 5> kColourFirstFormats{
    libcamera::formats::YUV420, libcamera::formats::NV12, libcamera::formats::NV21,
    libcamera::formats::YVU420, libcamera::formats::R8};

bool isLuminanceFirst(const libcamera::PixelFormat& format) {
    return std::find(kLuminanceFirstFormats.begin(), kLuminanceFirstFormats.end(), format) !=
           kLuminanceFirstFormats.end();
}

bool isInterleavedChroma(const libcamera::PixelFormat& format) {
    return format == libcamera::formats::NV12 || format == libcamera::formats::NV21;
}

bool isCrFirst(const libcamera::PixelFormat& format) {
    return format == libcamera::formats::NV21 || format == libcamera::formats::YVU420;
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
    std::string colourAbsence_;
    std::optional<std::int32_t> exposureUs_;  // set on every request queued again

private:
    // One buffer's planes, mapped (planes sharing a dmabuf share one mapping).
    struct Mapping {
        std::vector<std::pair<void*, std::size_t>> regions;  // to unmap
        std::span<const std::uint8_t> luminance;             // the first plane
        std::span<const std::uint8_t> cb, cr;                // the chroma, at their first samples
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
    libcamera::PixelFormat format_;
    int stride_ = 0;
    bool colour_ = false;  // colour asked for
    ChromaView chroma_;    // the geometry and encoding (spans per buffer)
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
        for (const auto& [base, length] : mapping.regions) {
            ::munmap(base, length);
        }
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
    colour_ = settings.colour;
    const std::array<libcamera::PixelFormat, 5>& formats =
        colour_ ? kColourFirstFormats : kLuminanceFirstFormats;
    const auto preferred = std::find_if(
        formats.begin(), formats.end(), [&offered](const libcamera::PixelFormat& format) {
            return std::find(offered.begin(), offered.end(), format) != offered.end();
        });
    if (preferred == formats.end()) {
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
    format_ = stream.pixelFormat;
    width_ = static_cast<int>(stream.size.width);
    height_ = static_cast<int>(stream.size.height);
    stride_ = static_cast<int>(stream.stride);
    if (width_ <= 0 || height_ <= 0 || stride_ < width_) {
        fail("configured an unusable stream " + stream.toString());
    }

    if (!colour_) {
        colourAbsence_ = "was not asked for colour";
    } else if (format_ == libcamera::formats::R8) {
        colourAbsence_ = "streams R8, which has no colour";
    } else {
        chroma_.width = (width_ + 1) / 2;
        chroma_.height = (height_ + 1) / 2;
        // libcamera's strides for 4:2:0: planar chroma rows are half the luminance's, an
        // interleaved CbCr row as long as it.
        chroma_.step = isInterleavedChroma(format_) ? 2 : 1;
        chroma_.stride = isInterleavedChroma(format_) ? stride_ : stride_ / 2;
        if (stream.colorSpace) {
            using Encoding = libcamera::ColorSpace::YcbcrEncoding;
            chroma_.encoding = stream.colorSpace->ycbcrEncoding == Encoding::Rec709
                                   ? ChromaView::Encoding::kRec709
                               : stream.colorSpace->ycbcrEncoding == Encoding::Rec2020
                                   ? ChromaView::Encoding::kRec2020
                                   : ChromaView::Encoding::kRec601;
            chroma_.fullRange = stream.colorSpace->range == libcamera::ColorSpace::Range::Full;
        }
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
    // One chroma plane's bytes (interleaved: the CbCr plane's, from its first Cb).
    const std::size_t chromaNeeded =
        chroma_.width == 0
            ? 0
            : static_cast<std::size_t>(chroma_.stride) *
                      static_cast<std::size_t>(chroma_.height - 1) +
                  static_cast<std::size_t>(chroma_.width) * static_cast<std::size_t>(chroma_.step);
    for (const std::unique_ptr<libcamera::FrameBuffer>& buffer : allocator_->buffers(stream_)) {
        const std::vector<libcamera::FrameBuffer::Plane>& planes = buffer->planes();
        const libcamera::FrameBuffer::Plane& plane = planes.front();
        if (plane.length < needed) {
            fail("gives a " + std::to_string(plane.length) + "-byte first plane, needs " +
                 std::to_string(needed));
        }
        Mapping& mapping = mappings_[buffer.get()];
        // mmap offsets must be page-aligned and a plane's need not be: map each dmabuf from its
        // start, far enough for every plane in it, and point into it.
        std::map<int, const std::uint8_t*> bases;
        for (const libcamera::FrameBuffer::Plane& each : planes) {
            const int fd = each.fd.get();
            if (bases.contains(fd)) {
                continue;
            }
            std::size_t length = 0;
            for (const libcamera::FrameBuffer::Plane& other : planes) {
                if (other.fd.get() == fd) {
                    length =
                        std::max(length, static_cast<std::size_t>(other.offset) + other.length);
                }
            }
            void* base = ::mmap(nullptr, length, PROT_READ, MAP_SHARED, fd, 0);
            if (base == MAP_FAILED) {
                fail(std::string("cannot map a frame buffer (") + std::strerror(errno) + ")");
            }
            mapping.regions.emplace_back(base, length);
            bases[fd] = static_cast<const std::uint8_t*>(base);
        }
        const auto spanOf = [&bases](const libcamera::FrameBuffer::Plane& each, std::size_t skip) {
            return std::span<const std::uint8_t>(bases.at(each.fd.get()) + each.offset + skip,
                                                 each.length - skip);
        };
        mapping.luminance = spanOf(plane, 0);
        if (chroma_.width == 0) {
            continue;
        }
        // The chroma planes: their own (YUV420: Y, U, V; NV12: Y, UV), or, when the pipeline
        // gives one plane for the whole image, after the luminance in the same bytes.
        std::span<const std::uint8_t> first, second;
        const std::size_t lumaBytes =
            static_cast<std::size_t>(stride_) * static_cast<std::size_t>(height_);
        const std::size_t planeBytes =
            static_cast<std::size_t>(chroma_.stride) * static_cast<std::size_t>(chroma_.height);
        if (planes.size() >= (chroma_.step == 2 ? 2u : 3u)) {
            first = spanOf(planes[1], 0);
            second = chroma_.step == 2 ? first.subspan(std::min<std::size_t>(1, first.size()))
                                       : spanOf(planes[2], 0);
        } else if (planes.size() == 1 && plane.length >= lumaBytes) {
            const std::span<const std::uint8_t> rest = spanOf(plane, lumaBytes);
            first = rest;
            second = chroma_.step == 2 ? rest.subspan(std::min<std::size_t>(1, rest.size()))
                                       : rest.subspan(std::min(planeBytes, rest.size()));
        }
        // Interleaved: the second component starts one byte in, so it needs one byte less.
        if (first.size() < chromaNeeded || second.size() + (chroma_.step - 1) < chromaNeeded) {
            colourAbsence_ = "gives buffers whose planes do not hold the " + format_.toString() +
                             " chroma (" + std::to_string(planes.size()) + " planes)";
            chroma_.width = 0;
            continue;
        }
        const bool crFirst = isCrFirst(format_);
        mapping.cb = crFirst ? second : first;
        mapping.cr = crFirst ? first : second;
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
        if (chroma_.width > 0) {
            ChromaView chroma = chroma_;
            chroma.cb = mapping.cb;
            chroma.cr = mapping.cr;
            frame.chroma = chroma;
        }
        if (const std::optional<std::int32_t> exposure =
                request->metadata().get(libcamera::controls::ExposureTime)) {
            frame.exposureUs = *exposure;
        }
        onFrame(frame);
    }
    for (libcamera::Request* request : completed) {
        request->reuse(libcamera::Request::ReuseBuffers);
        if (exposureUs_ && exposureFixed_) {
            request->controls().set(libcamera::controls::ExposureTime, *exposureUs_);
        }
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

const std::string& LibcameraStream::colourAbsence() const {
    return session_->colourAbsence_;
}

void LibcameraStream::setExposureUs(std::int32_t exposureUs) {
    session_->exposureUs_ = exposureUs;
}

void LibcameraStream::drain(const std::function<void(const CameraFrameView&)>& onFrame,
                            bool newestOnly) {
    session_->drain(onFrame, newestOnly);
}

}  // namespace vpe::firmware
