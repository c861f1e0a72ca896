// A Communicator whose ranks are threads of this process (the tests of run_survey_distributed
// without MPI): every collective is two barriers around a shared table.
#pragma once

#include <algorithm>
#include <barrier>
#include <exception>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "beamtrace/core/communicator.hpp"

namespace beamtrace::test {

class ThreadWorld {
  public:
    explicit ThreadWorld(int size)
        : size_(size),
          sync_(size),
          u64_(static_cast<std::size_t>(size)),
          i64_(static_cast<std::size_t>(size)),
          text_(static_cast<std::size_t>(size)) {}

    /// Runs body(comm) on `size` threads, one rank each; returns when all are done.
    void run(const std::function<void(Communicator&)>& body);

  private:
    friend class ThreadCommunicator;
    int size_;
    std::barrier<> sync_;
    std::vector<std::vector<std::uint64_t>> u64_;
    std::vector<std::vector<std::int64_t>> i64_;
    std::vector<std::string> text_;
};

class ThreadCommunicator final : public Communicator {
  public:
    ThreadCommunicator(ThreadWorld& world, int rank) : world_(world), rank_(rank) {}
    [[nodiscard]] int rank() const override { return rank_; }
    [[nodiscard]] int size() const override { return world_.size_; }
    void sum(std::span<std::uint64_t> values) override {
        mine_u64().assign(values.begin(), values.end());
        world_.sync_.arrive_and_wait();
        for (std::size_t i = 0; i < values.size(); ++i) {
            values[i] = 0;
            for (const auto& v : world_.u64_) {
                values[i] += v.at(i);
            }
        }
        world_.sync_.arrive_and_wait();
    }
    void min(std::span<std::int64_t> values) override {
        world_.i64_[static_cast<std::size_t>(rank_)].assign(values.begin(), values.end());
        world_.sync_.arrive_and_wait();
        for (std::size_t i = 0; i < values.size(); ++i) {
            for (const auto& v : world_.i64_) {
                values[i] = std::min(values[i], v.at(i));
            }
        }
        world_.sync_.arrive_and_wait();
    }
    [[nodiscard]] std::vector<std::uint64_t> all_gather(std::uint64_t value) override {
        mine_u64().assign(1, value);
        world_.sync_.arrive_and_wait();
        std::vector<std::uint64_t> out;
        for (const auto& v : world_.u64_) {
            out.push_back(v.at(0));
        }
        world_.sync_.arrive_and_wait();
        return out;
    }
    [[nodiscard]] std::string broadcast(const std::string& text, int root) override {
        world_.text_[static_cast<std::size_t>(rank_)] = text;
        world_.sync_.arrive_and_wait();
        std::string out = world_.text_[static_cast<std::size_t>(root)];
        world_.sync_.arrive_and_wait();
        return out;
    }
    [[nodiscard]] std::unique_ptr<SharedFile> open_shared(
        const std::filesystem::path& path) override {
        // Every rank passes both barriers, also when its open fails (then it throws after them).
        std::unique_ptr<SharedFile> file;
        std::exception_ptr error;
        for (const bool creator : {true, false}) {
            if ((rank_ == 0) == creator) {
                try {
                    file = open_posix_shared_file(path, creator);
                } catch (...) {
                    error = std::current_exception();
                }
            }
            world_.sync_.arrive_and_wait();
        }
        if (error) {
            std::rethrow_exception(error);
        }
        return file;
    }

  private:
    std::vector<std::uint64_t>& mine_u64() { return world_.u64_[static_cast<std::size_t>(rank_)]; }
    ThreadWorld& world_;
    int rank_;
};

inline void ThreadWorld::run(const std::function<void(Communicator&)>& body) {
    std::vector<std::thread> ranks;
    for (int r = 0; r < size_; ++r) {
        ranks.emplace_back([this, r, &body] {
            ThreadCommunicator comm(*this, r);
            body(comm);
        });
    }
    for (auto& t : ranks) {
        t.join();
    }
}

}  // namespace beamtrace::test
