// The survey's shelves of spare block memory: last in first out, a new value when none is spare,
// shared by threads (the pool's threads take point blocks, the writer thread puts them back).
#include "pipeline/detail/survey_block.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <thread>
#include <vector>

#include "beamtrace/io/point_sink.hpp"

namespace beamtrace::detail {
namespace {

TEST(Shelf, GivesBackTheLastPutFirstAndANewOneWhenEmpty) {
    Shelf<PointBlock> shelf;
    PointBlock a, b;
    a.points.resize(3);
    b.points.resize(5);
    const BlockPoint* a_memory = a.points.data();
    const BlockPoint* b_memory = b.points.data();
    shelf.put(std::move(a));
    shelf.put(std::move(b));
    PointBlock first = shelf.take();
    EXPECT_EQ(first.points.data(), b_memory);  // the memory itself, not a copy
    EXPECT_EQ(first.points.size(), 5u);
    PointBlock second = shelf.take();
    EXPECT_EQ(second.points.data(), a_memory);
    const PointBlock fresh = shelf.take();
    EXPECT_TRUE(fresh.points.empty());
    EXPECT_EQ(fresh.points.capacity(), 0u);
}

TEST(Shelf, MakesTheElementOfAPointerWhenEmpty) {
    WorkShelf shelf;
    std::unique_ptr<BlockWork> w = shelf.take();
    ASSERT_NE(w, nullptr);
    BlockWork* kept = w.get();
    shelf.put(std::move(w));
    EXPECT_EQ(shelf.take().get(), kept);
}

TEST(Shelf, ThreadsTakingAndPuttingLoseNothing) {
    Shelf<std::unique_ptr<int>> shelf;
    std::vector<std::thread> threads;
    std::vector<std::set<int*>> seen(4);
    for (int t = 0; t < 4; ++t) {
        threads.emplace_back([&shelf, &seen, t] {
            for (int i = 0; i < 2000; ++i) {
                std::unique_ptr<int> v = shelf.take();
                seen[static_cast<std::size_t>(t)].insert(v.get());
                shelf.put(std::move(v));
            }
        });
    }
    for (auto& th : threads) {
        th.join();
    }
    // At most one value per thread was ever made: each thread put its value back before taking.
    std::set<int*> all;
    for (const auto& s : seen) {
        all.insert(s.begin(), s.end());
    }
    EXPECT_LE(all.size(), 4u);
    EXPECT_GE(all.size(), 1u);
}

}  // namespace
}  // namespace beamtrace::detail
