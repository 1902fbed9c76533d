// app/frame_writer.h — writes finished frames while the next one renders (issue 13).
//
// A render job hands each finished frame's files (targets when asked, then the display image) to
// one background thread that encodes and writes them through core/io.h, so every write keeps its
// guarantees (encoded in memory, flushed and checked, renamed into place). At most
// `max_in_flight` frames wait: memory stays bounded, and a slow disk holds the renderer back
// instead of piling up frames. Files are written in submission order; the bytes do not depend on
// the overlap. A frame is written as a set (Frame::claim): every file prepared first, then all put
// in place. The first failure stops the job: submit() and finish() rethrow it, and nothing is
// written after it.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/image.h"
#include "core/io.h"

namespace aq::app {

class FrameWriter {
public:
    //! One file: `image` written to `path`; `drop_alpha`: an RGBA image written as its RGB
    //! (core/io.h write_image; a stylised painting handed over without a copy).
    struct File {
        std::string path;
        ImageF image;
        bool drop_alpha = false;
        File(std::string p, ImageF img, bool drop = false) : path(std::move(p)), image(std::move(img)), drop_alpha(drop) {}
    };
    struct Frame {
        std::vector<File> files;  //!< written in order
        std::string done_message;                          //!< reported once every file is written
        std::string description;  //!< embedded in every file (core/io.h write_image), may be empty
        Compression compression = Compression::Fast;  //!< of every file (core/io.h write_image)
        //! Called on the writer thread once every file is written, with the SHA-256 of each file's
        //! bytes in `files` order (the provenance sidecar, app/manifest.h) and the wall ms spent
        //! encoding and writing them (to temporaries) and renaming them into place. A throw stops
        //! the job like a write failure.
        std::function<void(const std::vector<std::string>& sha256, double write_ms, double commit_ms)> after;
        //! The file that claims the set (the provenance sidecar `after` writes), or empty. While the
        //! frame is written its WriteLock is held (a second process writing it is refused), and the
        //! old claim is removed only once every new file is written and flushed, just before they
        //! are renamed into place: a failure leaves the old set whole, and a kill in the renames
        //! leaves no claim on files that are not its own.
        std::string claim;
    };

    //! max_in_flight >= 1 frames may wait; `report` is called from the writer thread.
    FrameWriter(std::size_t max_in_flight, std::function<void(const std::string&)> report);
    //! Writes what is queued (complete frames of a job that then failed elsewhere are kept, as
    //! when frames were written in line), then stops. Errors are only reported by finish().
    ~FrameWriter();
    FrameWriter(const FrameWriter&) = delete;
    FrameWriter& operator=(const FrameWriter&) = delete;

    //! Queues a frame; blocks while max_in_flight frames wait. Rethrows an earlier write failure.
    void submit(Frame frame);
    //! Waits until every queued frame is written; rethrows the first failure.
    void finish();

private:
    void run();

    std::size_t max_in_flight_;
    std::function<void(const std::string&)> report_;
    std::mutex m_;
    std::condition_variable cv_;
    std::deque<Frame> queue_;
    bool busy_ = false, stop_ = false;
    std::exception_ptr error_;
    std::thread thread_;  // last: started after every other member exists
};

}  // namespace aq::app
