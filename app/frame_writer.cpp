// app/frame_writer.cpp — see frame_writer.h.
#include "app/frame_writer.h"

#include <chrono>

#include <unistd.h>

#include <optional>

#include "core/io.h"

namespace aq::app {

FrameWriter::FrameWriter(std::size_t max_in_flight, std::function<void(const std::string&)> report)
    : max_in_flight_(max_in_flight < 1 ? 1 : max_in_flight), report_(std::move(report)), thread_([this] { run(); }) {}

FrameWriter::~FrameWriter() {
    {
        std::lock_guard<std::mutex> lock(m_);
        stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
}

void FrameWriter::submit(Frame frame) {
    std::unique_lock<std::mutex> lock(m_);
    cv_.wait(lock, [&] { return error_ || queue_.size() < max_in_flight_; });
    if (error_) std::rethrow_exception(error_);
    queue_.push_back(std::move(frame));
    cv_.notify_all();
}

void FrameWriter::finish() {
    std::unique_lock<std::mutex> lock(m_);
    cv_.wait(lock, [&] { return error_ || (queue_.empty() && !busy_); });
    if (error_) std::rethrow_exception(error_);
}

void FrameWriter::run() {
    for (;;) {
        Frame f;
        {
            std::unique_lock<std::mutex> lock(m_);
            cv_.wait(lock, [&] { return stop_ || !queue_.empty(); });
            if (queue_.empty()) return;  // stop_ and nothing left
            f = std::move(queue_.front());
            queue_.pop_front();
            busy_ = true;
        }
        std::exception_ptr err;
        try {
            std::optional<WriteLock> lock;
            if (!f.claim.empty()) lock.emplace(f.claim);
            std::vector<std::string> sha(f.files.size());
            std::vector<PreparedFile> prepared;
            prepared.reserve(f.files.size());
            using clock = std::chrono::steady_clock;
            auto ms = [](clock::time_point a, clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
            const clock::time_point t0 = clock::now();
            for (std::size_t i = 0; i < f.files.size(); ++i) {
                const File& file = f.files[i];
                prepared.push_back(prepare_image(file.path, file.image, &sha[i], f.description, f.compression, file.drop_alpha));
            }
            const clock::time_point t1 = clock::now();
            if (!f.claim.empty()) ::unlink(f.claim.c_str());  // the old set's claim, gone before its files change
            for (PreparedFile& p : prepared) p.commit();
            if (f.after) f.after(sha, ms(t0, t1), ms(t1, clock::now()));
            if (report_ && !f.done_message.empty()) report_(f.done_message);
        } catch (...) {
            err = std::current_exception();
        }
        {
            std::lock_guard<std::mutex> lock(m_);
            busy_ = false;
            if (err && !error_) {
                error_ = err;
                queue_.clear();  // nothing is written after a failure
            }
        }
        cv_.notify_all();
    }
}

}  // namespace aq::app
