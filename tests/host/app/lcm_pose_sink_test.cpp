#include "app/lcm_pose_sink.h"

#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>

#include "ale_lcm/pose_t.hpp"
#include "ale_lcm/status_t.hpp"

namespace ale::app {
namespace {

// Subscribed with subscribeFunction (a plain function and a context pointer), not with a member
// function: LCM's member-function subscription calls `(subs->handler->*subs->handlerMethod)(...)`,
// and GCC 12 miscompiles exactly that form (the object of a pointer-to-member call read through a
// polymorphic object) under -fsanitize=vptr: one branch of the virtual/non-virtual dispatch uses a
// register it never loaded, so the handler gets a garbage `this` (the host-asan crash in LCM's
// dispatch). A 15-line program without LCM reproduces it; the plain build is unaffected.
struct Receiver {
  std::vector<ale_lcm::pose_t> poses;
  std::vector<ale_lcm::status_t> statuses;
  static void on_pose(const lcm::ReceiveBuffer*, const std::string&, const ale_lcm::pose_t* m, Receiver* self) {
    self->poses.push_back(*m);
  }
  static void on_status(const lcm::ReceiveBuffer*, const std::string&, const ale_lcm::status_t* m, Receiver* self) {
    self->statuses.push_back(*m);
  }
};

// memq:// keeps everything inside the process: nothing goes on the network.
TEST(LcmPoseSinkTest, RoundTripsPoseAndStatusInProcess) {
  auto sink = LcmPoseSink::open("memq://", "ALE_POSE", "ALE_STATUS");
  ASSERT_TRUE(sink.ok()) << sink.status().to_string();
  Receiver rx;
  (*sink)->lcm().subscribeFunction("ALE_POSE", &Receiver::on_pose, &rx);
  (*sink)->lcm().subscribeFunction("ALE_STATUS", &Receiver::on_status, &rx);

  hal::PoseEstimate p;
  p.timestamp_ns = 1403715273262142976LL;
  p.frame_sequence = 7;
  p.state = TrackingState::kTracking;
  p.p_wc = {1.5, -2.0, 0.25};
  p.q_wc = {0.5, 0.5, -0.5, 0.5};
  ASSERT_TRUE((*sink)->publish(p).ok());
  hal::StatusReport r;
  r.timestamp_ns = p.timestamp_ns;
  r.brightness = BrightnessClass::kDark;
  r.features = 987;
  r.message = "ok";
  ASSERT_TRUE((*sink)->publish(r).ok());
  while ((*sink)->lcm().handleTimeout(0) > 0) {
  }
  ASSERT_EQ(rx.poses.size(), 1u);
  EXPECT_EQ(rx.poses[0].timestamp_ns, p.timestamp_ns);
  EXPECT_EQ(rx.poses[0].frame_sequence, 7);
  EXPECT_EQ(rx.poses[0].state, static_cast<int8_t>(TrackingState::kTracking));
  EXPECT_DOUBLE_EQ(rx.poses[0].position[1], -2.0);
  EXPECT_DOUBLE_EQ(rx.poses[0].orientation[2], -0.5);
  ASSERT_EQ(rx.statuses.size(), 1u);
  EXPECT_EQ(rx.statuses[0].brightness_class, static_cast<int8_t>(BrightnessClass::kDark));
  EXPECT_EQ(rx.statuses[0].features, 987);
  EXPECT_EQ(rx.statuses[0].message, "ok");
}

TEST(LcmPoseSinkTest, BadUrlIsAClearError) {
  auto sink = LcmPoseSink::open("nosuchprovider://x", "A", "B");
  ASSERT_FALSE(sink.ok());
  EXPECT_EQ(sink.status().code(), StatusCode::kUnavailable);
  EXPECT_NE(sink.status().message().find("nosuchprovider://x"), std::string::npos);
}

}  // namespace
}  // namespace ale::app
