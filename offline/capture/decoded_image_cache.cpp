// SPDX-License-Identifier: MIT
// The decoded images of the process, keyed by file, size and modification time.
#include "vpe/capture/decoded_image_cache.h"

#include <algorithm>
#include <system_error>

namespace vpe::capture {

namespace {

// The file's identity now: false when it cannot be read (then nothing is cached for it).
bool identify(const std::filesystem::path& file, std::uintmax_t& size,
              std::filesystem::file_time_type& modified) {
    std::error_code error;
    size = std::filesystem::file_size(file, error);
    if (error) {
        return false;
    }
    modified = std::filesystem::last_write_time(file, error);
    return !error;
}

}  // namespace

DecodedImageCache& DecodedImageCache::instance() {
    static DecodedImageCache cache(std::size_t{1} << 30);
    return cache;
}

std::shared_ptr<const DecodedImageCache::Image> DecodedImageCache::find(
    const std::filesystem::path& file) const {
    std::uintmax_t size = 0;
    std::filesystem::file_time_type modified;
    if (!identify(file, size, modified)) {
        return nullptr;
    }
    const std::lock_guard lock(mutex_);
    for (const Entry& entry : entries_) {
        if (entry.file == file && entry.fileSize == size && entry.modified == modified) {
            return entry.image;
        }
    }
    return nullptr;
}

void DecodedImageCache::insert(const std::filesystem::path& file,
                               std::shared_ptr<const Image> image) {
    Entry entry;
    entry.file = file;
    if (!image || !admits(image->bytes.size()) || !identify(file, entry.fileSize, entry.modified)) {
        return;
    }
    const std::lock_guard lock(mutex_);
    const auto same = std::find_if(entries_.begin(), entries_.end(),
                                   [&](const Entry& held) { return held.file == file; });
    if (same != entries_.end()) {
        heldBytes_ -= same->image->bytes.size();
        entries_.erase(same);
    }
    if (heldBytes_ + image->bytes.size() > budgetBytes_) {
        entries_.clear();
        heldBytes_ = 0;
    }
    heldBytes_ += image->bytes.size();
    entry.image = std::move(image);
    entries_.push_back(std::move(entry));
}

}  // namespace vpe::capture
