// SPDX-License-Identifier: MIT
// BundleFile: a read-only private mapping of the whole file, validated by BundleView::parse.
#include <cerrno>
#include <cstring>
#include <limits>
#include <utility>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "vpe/proto/bundle.h"

namespace vpe::proto {

namespace {

// Closes the descriptor when the mapping is made (the mapping keeps the file alive).
class FileDescriptor {
public:
    explicit FileDescriptor(int fd) : fd_(fd) {}
    ~FileDescriptor() {
        if (fd_ >= 0) {
            ::close(fd_);
        }
    }
    FileDescriptor(const FileDescriptor&) = delete;
    FileDescriptor& operator=(const FileDescriptor&) = delete;
    int get() const { return fd_; }

private:
    int fd_;
};

}  // namespace

BundleFile BundleFile::open(const std::filesystem::path& path, const BundleOpenOptions& options) {
    const std::string name = path.string();
    const FileDescriptor file(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
    if (file.get() < 0) {
        throw BundleError(name, std::string("cannot open: ") + std::strerror(errno));
    }
    struct stat status {};
    if (::fstat(file.get(), &status) != 0) {
        throw BundleError(name, std::string("cannot stat: ") + std::strerror(errno));
    }
    if (!S_ISREG(status.st_mode)) {
        throw BundleError(name, "not a regular file");
    }
    if (status.st_size == 0) {
        throw BundleError(name, "empty file");  // (mmap refuses empty mappings)
    }
    if (static_cast<std::uintmax_t>(status.st_size) > std::numeric_limits<std::size_t>::max()) {
        throw BundleError(name, "too large to map on this system");
    }
    const auto size = static_cast<std::size_t>(status.st_size);
    void* mapping = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, file.get(), 0);
    if (mapping == MAP_FAILED) {
        throw BundleError(name, std::string("cannot map: ") + std::strerror(errno));
    }
    try {
        const std::span<const std::byte> bytes(static_cast<const std::byte*>(mapping), size);
        return BundleFile(mapping, size, BundleView::parse(bytes, name, options));
    } catch (...) {
        ::munmap(mapping, size);
        throw;
    }
}

BundleFile::BundleFile(void* mapping, std::size_t size, BundleView view)
    : mapping_(mapping), size_(size), view_(std::move(view)) {}

BundleFile::~BundleFile() {
    unmap();
}

BundleFile::BundleFile(BundleFile&& other) noexcept
    : mapping_(std::exchange(other.mapping_, nullptr)),
      size_(std::exchange(other.size_, 0)),
      view_(std::move(other.view_)) {}

BundleFile& BundleFile::operator=(BundleFile&& other) noexcept {
    if (this != &other) {
        unmap();
        mapping_ = std::exchange(other.mapping_, nullptr);
        size_ = std::exchange(other.size_, 0);
        view_ = std::move(other.view_);
    }
    return *this;
}

void BundleFile::unmap() {
    if (mapping_ != nullptr) {
        ::munmap(mapping_, size_);
        mapping_ = nullptr;
    }
}

}  // namespace vpe::proto
