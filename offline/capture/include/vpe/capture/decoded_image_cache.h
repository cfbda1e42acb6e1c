// SPDX-License-Identifier: MIT
// DecodedImageCache: the decoded scanlines of whole images, kept for the process. An extended
// fit passes over a capture's images up to seven times (photometric stereo, each held-out
// search's grid, the fit itself); ImageBandReader decodes each image once and reads it back from
// here. Bounded by a budget: a capture whose codes do not fit streams from its files as before,
// its memory growing with the band, not the image.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <vector>

namespace vpe::capture {

class DecodedImageCache {
public:
    // One image as decoded: rows of width × channels values of valueBytes each (8-bit, 16-bit
    // or float, as the reader decodes them), top to bottom.
    struct Image {
        int width = 0;
        int height = 0;
        int channels = 0;
        int valueBytes = 0;
        std::vector<unsigned char> bytes;
    };

    // The process's cache; `budgetBytes` is how much it may hold (1 GiB).
    static DecodedImageCache& instance();
    explicit DecodedImageCache(std::size_t budgetBytes) : budgetBytes_(budgetBytes) {}

    // `file` decoded, when it is held and the file is unchanged since (size and modification
    // time); null otherwise.
    std::shared_ptr<const Image> find(const std::filesystem::path& file) const;
    // Whether an image of `bytes` may be kept: no larger than the budget.
    bool admits(std::size_t bytes) const { return bytes <= budgetBytes_; }
    // Keeps `image`, decoded from `file` as it is now. To stay within the budget it first drops
    // what it held (a process reads one capture at a time; a shared image stays alive for its
    // readers).
    void insert(const std::filesystem::path& file, std::shared_ptr<const Image> image);

private:
    struct Entry {
        std::filesystem::path file;
        std::uintmax_t fileSize = 0;
        std::filesystem::file_time_type modified;
        std::shared_ptr<const Image> image;
    };
    std::size_t budgetBytes_;
    std::size_t heldBytes_ = 0;
    mutable std::mutex mutex_;
    std::vector<Entry> entries_;
};

}  // namespace vpe::capture
