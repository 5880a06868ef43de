#include <catch2/catch.hpp>

#include "core/angles.h"
#include "core/error.h"
#include "hw/protocol_gantry.h"
#include "sim_gantry_link.h"

using namespace acq;

namespace {

const ArmAngles kTarget{DegToRad(40), DegToRad(-30), DegToRad(20), DegToRad(150)};

// Measured angles within 1 millidegree (the protocol's resolution) of the target.
void RequireAt(const GantryStatus& s, const ArmAngles& t) {
  REQUIRE(s.measured.light_theta == Approx(t.light_theta).margin(DegToRad(0.001)));
  REQUIRE(s.measured.light_phi == Approx(t.light_phi).margin(DegToRad(0.001)));
  REQUIRE(s.measured.camera_theta == Approx(t.camera_theta).margin(DegToRad(0.001)));
  REQUIRE(s.measured.camera_phi == Approx(t.camera_phi).margin(DegToRad(0.001)));
}

}  // namespace

TEST_CASE("handshake: same schema connects, another is refused with the fix", "[gantry]") {
  sim::SimGantryFirmware fw;
  test::SimGantryLink link(fw);
  CHECK_NOTHROW(ProtocolGantry(link));
  sim::FirmwareOptions other;
  other.schema_hash = 0x12345678;
  sim::SimGantryFirmware old(other);
  test::SimGantryLink old_link(old);
  CHECK_THROWS_WITH(ProtocolGantry(old_link),
                    Catch::Contains("schema 0x12345678") && Catch::Contains("flash the firmware"));
}

TEST_CASE("home, move, arrive; a move before homing is refused", "[gantry]") {
  sim::SimGantryFirmware fw;
  test::SimGantryLink link(fw);
  ProtocolGantry g(link);
  CHECK_THROWS_WITH(g.MoveTo(kTarget), Catch::Contains("not homed"));
  g.Home();
  MoveAndWait(g, kTarget, 10);
  const GantryStatus s = g.Status();
  CHECK(s.Homed());
  CHECK_FALSE(s.Moving());
  CHECK(s.fault_bits == 0);
  RequireAt(s, kTarget);
  CHECK(fw.executed_moves() == 1);
}

TEST_CASE("lost and corrupted frames: retransmitted, recovered, no move executed twice",
          "[gantry]") {
  sim::SimGantryFirmware fw;
  fw.faults.drop_reply_probability = 0.3;
  fw.faults.corrupt_reply_probability = 0.2;
  test::SimGantryLink link(fw);
  link.drop_request_probability = 0.2;
  ProtocolGantryOptions o;
  o.attempts = 20;  // with ~55% of exchanges failing, 20 tries fail together with p < 1e-5
  // Each lost exchange costs a reply timeout; 200 ms timeouts on a link this bad add up past
  // the 2 s motion lease and the firmware rightly stops the arms. A USB round trip is about a
  // millisecond, so 20 ms is the realistic timeout here.
  o.reply_timeout_ms = 20;
  ProtocolGantry g(link, o);
  g.Home();
  const ArmAngles targets[] = {kTarget,
                               {DegToRad(60), DegToRad(10), DegToRad(35), DegToRad(-120)},
                               {DegToRad(30), 0, DegToRad(10), DegToRad(180)}};
  for (const ArmAngles& t : targets) {
    MoveAndWait(g, t, 20);
    RequireAt(g.Status(), t);
  }
  CHECK(g.retransmissions() > 0);
  CHECK(fw.executed_moves() == 3);  // each accepted exactly once, retransmissions or not
}

TEST_CASE("targets that collide or are out of reach are refused, naming the rule", "[gantry]") {
  sim::SimGantryFirmware fw;
  test::SimGantryLink link(fw);
  ProtocolGantry g(link);
  g.Home();
  g.RenewLease(1000);
  CHECK_THROWS_WITH(g.MoveTo({DegToRad(30), 0, DegToRad(32), 0}), Catch::Contains("collision"));
  CHECK_THROWS_WITH(g.MoveTo({DegToRad(89), 0, DegToRad(20), 0}), Catch::Contains("reach"));
  CHECK(fw.executed_moves() == 0);
}

TEST_CASE(
    "a stalled axis, a tripped limit, an emergency stop and a lapsed lease each stop the "
    "arms and latch a fault",
    "[gantry]") {
  sim::SimGantryFirmware fw;
  test::SimGantryLink link(fw);
  ProtocolGantry g(link);
  g.Home();
  MoveAndWait(g, kTarget, 10);

  fw.faults.stalled_axis = GP_AXIS_LIGHT_PHI;
  // The fault named as the protocol's vocabulary names it (gantry_vocabulary.def).
  CHECK_THROWS_WITH(MoveAndWait(g, {DegToRad(50), DegToRad(20), DegToRad(25), DegToRad(140)}, 10),
                    Catch::Contains("fault during the move: STALL (an axis did not follow"));
  GantryStatus s = g.Status();
  CHECK((s.fault_bits & GP_FAULT_BIT_STALL) != 0);
  CHECK_FALSE(s.Moving());
  CHECK_THROWS_WITH(g.MoveTo(kTarget), Catch::Contains("fault is latched"));
  fw.faults.stalled_axis = -1;
  g.ClearFaults(0xFFFF);
  MoveAndWait(g, kTarget, 10);
  RequireAt(g.Status(), kTarget);

  fw.faults.trip_limit = true;
  CHECK_THROWS(MoveAndWait(g, {DegToRad(45), 0, 0, 0}, 10));
  CHECK((g.Status().fault_bits & GP_FAULT_BIT_LIMIT) != 0);
  g.ClearFaults(0xFFFF);

  g.RenewLease(5000);
  g.MoveTo({DegToRad(70), DegToRad(90), DegToRad(10), 0});
  g.EmergencyStop();  // mid-move
  s = g.Status();
  CHECK_FALSE(s.Moving());
  CHECK((s.fault_bits & GP_FAULT_BIT_ESTOP) != 0);
  CHECK_NOTHROW(g.EmergencyStop());  // accepted in every state
  g.ClearFaults(0xFFFF);

  g.RenewLease(100);  // 0.1 s of lease for a move of several seconds, never renewed
  g.MoveTo({DegToRad(30), DegToRad(-90), DegToRad(40), DegToRad(90)});
  for (int i = 0; i < 50; ++i) s = g.Status();  // about 0.25 s of simulated time
  CHECK((s.fault_bits & GP_FAULT_BIT_LEASE_EXPIRED) != 0);
  CHECK_FALSE(s.Moving());
}

TEST_CASE("a silent or unplugged device ends in a clear error, never a hang", "[gantry]") {
  sim::SimGantryFirmware fw;
  test::SimGantryLink link(fw);
  ProtocolGantryOptions o;
  o.reply_timeout_ms = 20;
  o.attempts = 3;
  ProtocolGantry g(link, o);
  fw.faults.drop_reply_probability = 1.0;
  CHECK_THROWS_WITH(g.Status(), Catch::Contains("no answer to GET_STATUS after 3 attempts"));
  fw.faults.drop_reply_probability = 0;
  link.unplugged = true;
  CHECK_THROWS_WITH(g.Status(), Catch::Contains("USB device gone"));
}

TEST_CASE("move timeouts follow the move; a gantry slower than the plan says is caught",
          "[gantry]") {
  const TrapezoidProfile axis{DegToRad(30), DegToRad(60)};
  // 90 degrees: 3 s cruising plus 0.5 s of ramps, 0.5 s settle; x1.5 + 2 s of margin.
  CHECK(MoveTimeoutSeconds({0, 0, 0, 0}, {DegToRad(90), 0, 0, 0}, axis, 0.5) ==
        Approx(1.5 * 4.0 + 2));
  CHECK(MoveTimeoutSeconds(kTarget, kTarget, axis, 0.5) == Approx(1.5 * 0.5 + 2));

  sim::FirmwareOptions slow;
  slow.axis = {DegToRad(5), DegToRad(10)};  // six times slower than the host is told
  sim::SimGantryFirmware fw(slow);
  test::SimGantryLink link(fw);
  ProtocolGantry g(link);
  g.Home();
  while (g.Status().Moving()) {
  }
  CHECK_THROWS_WITH(MoveAndWait(g, kTarget, axis, 0.5), Catch::Contains("did not arrive within"));
  sim::SimGantryFirmware right;
  test::SimGantryLink right_link(right);
  ProtocolGantry ok(right_link);
  ok.Home();
  CHECK_NOTHROW(MoveAndWait(ok, kTarget, axis, 0.5));
}
