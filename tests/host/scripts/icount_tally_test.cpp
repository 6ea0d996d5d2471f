// The bookkeeping of scripts/arm-icount.sh's qemu plugin (scripts/icount/tally.h), driven the way
// qemu drives it: every start of a block adds the block's instructions to the total and one to
// the block's execs; a probe switches the slot.
#include "tally.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

class Tally : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_EQ(icount_tally_init(&t_, 1, 1), 0); }
  void TearDown() override { icount_tally_free(&t_); }
  icount_block* block(std::uint32_t insns, const char* func) {
    icount_block* b = icount_tally_block(&t_, insns, icount_tally_function(&t_, func));
    EXPECT_NE(b, nullptr);
    return b;
  }
  void run(icount_block* b, int times = 1) {
    b->execs += static_cast<std::uint64_t>(times);
    t_.total += static_cast<std::uint64_t>(times) * b->insns;
  }
  std::uint64_t frame(std::size_t f, int slot) const { return t_.frames[f * ICOUNT_MAX_SLOTS + static_cast<std::size_t>(slot)]; }
  std::string written() {
    std::FILE* f = std::tmpfile();
    EXPECT_EQ(icount_tally_write(&t_, f, nullptr), 0);
    std::rewind(f);
    std::string s;
    for (int c; (c = std::fgetc(f)) != EOF;) s += static_cast<char>(c);
    std::fclose(f);
    return s;
  }
  icount_tally t_{};
};

TEST_F(Tally, ChargesSlotsFramesAndFunctions) {
  icount_block* start = block(10, "_start");
  icount_block* a = block(3, "extract");
  icount_block* b = block(5, "track");
  icount_block* io = block(2, "read_png");
  run(start);                     // start-up: prologue, slot 0
  icount_tally_switch(&t_, 1);    // frame 0
  run(a, 2);
  icount_tally_switch(&t_, 7);
  run(b);
  run(a);                         // a shared helper called from the track stage
  icount_tally_switch(&t_, 0);
  run(io);
  icount_tally_switch(&t_, 1);    // frame 1
  run(a);
  icount_tally_finish(&t_);

  EXPECT_EQ(t_.total, 10u + 6 + 5 + 3 + 2 + 3);
  EXPECT_EQ(t_.prologue, 10u);
  EXPECT_EQ(t_.slot[0], 12u);
  EXPECT_EQ(t_.slot[1], 9u);
  EXPECT_EQ(t_.slot[7], 8u);
  ASSERT_EQ(t_.n_frames, 2u);
  EXPECT_EQ(frame(0, 1), 6u);
  EXPECT_EQ(frame(0, 7), 8u);
  EXPECT_EQ(frame(0, 0), 2u);
  EXPECT_EQ(frame(1, 1), 3u);
  EXPECT_EQ(frame(1, 7), 0u);
  const icount_function& extract = t_.funcs[a->func];
  EXPECT_EQ(extract.slot[1], 9u);
  EXPECT_EQ(extract.slot[7], 3u);
  EXPECT_EQ(t_.funcs[b->func].slot[7], 5u);
  EXPECT_EQ(t_.funcs[io->func].slot[0], 2u);

  const std::string r = written();
  EXPECT_NE(r.find("total_instructions 29\n"), std::string::npos) << r;
  EXPECT_NE(r.find("frames 2\nprologue 10\n"), std::string::npos) << r;
  EXPECT_NE(r.find("slot 7 8\n"), std::string::npos) << r;
  // per slot, by count: extract's 3 in slot 7 after track's 5
  EXPECT_NE(r.find("function 7 5 track\nfunction 7 3 extract\n"), std::string::npos) << r;
}

TEST_F(Tally, InternsFunctionsByText) {
  const std::string x = "f";
  const std::string y = "f";
  EXPECT_EQ(icount_tally_function(&t_, x.c_str()), icount_tally_function(&t_, y.c_str()));
  EXPECT_EQ(icount_tally_function(&t_, nullptr), icount_tally_function(&t_, "?"));
  EXPECT_NE(icount_tally_function(&t_, "f"), icount_tally_function(&t_, "g"));
  // past the first hash table's size
  std::vector<std::string> names;
  for (int i = 0; i < 3000; ++i) names.push_back("fn" + std::to_string(i));
  std::vector<std::uint32_t> ids;
  for (const std::string& n : names) ids.push_back(icount_tally_function(&t_, n.c_str()));
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string again = names[i];
    ASSERT_EQ(icount_tally_function(&t_, again.c_str()), ids[i]);
    ASSERT_STREQ(t_.funcs[ids[i]].name, names[i].c_str());
  }
}

TEST_F(Tally, BlocksKeepTheirAddressesAcrossChunks) {
  std::vector<icount_block*> blocks;
  for (std::uint32_t i = 0; i < 10000; ++i) blocks.push_back(block(i % 7 + 1, "f"));
  icount_tally_switch(&t_, 1);
  std::uint64_t want = 0;
  for (icount_block* b : blocks) {
    run(b);
    want += b->insns;
  }
  icount_tally_finish(&t_);
  EXPECT_EQ(t_.slot[1], want);
  EXPECT_EQ(t_.funcs[blocks.front()->func].slot[1], want);
  for (std::size_t i = 0; i < blocks.size(); ++i) ASSERT_EQ(blocks[i]->insns, i % 7 + 1);
}

TEST_F(Tally, ProbesOutOfRangeGoToSlotZeroAndAreCounted) {
  icount_block* a = block(4, "f");
  icount_tally_switch(&t_, ICOUNT_MAX_SLOTS + 3);
  run(a);
  icount_tally_finish(&t_);
  EXPECT_EQ(t_.slot[0], 4u);
  EXPECT_EQ(t_.unknown_probes, 1u);
  EXPECT_NE(written().find("unknown_probes 1\n"), std::string::npos);
}

TEST(TallyInit, RejectsAFrameSlotOutOfRange) {
  icount_tally t{};
  EXPECT_EQ(icount_tally_init(&t, ICOUNT_MAX_SLOTS, 0), -1);
  icount_tally_free(&t);
  EXPECT_EQ(icount_tally_init(&t, -1, 0), -1);
  icount_tally_free(&t);
}

}  // namespace
