/// `robcal iso9283 plan|analyse`: the ISO 9283 test cube, its poses P1–P5 and cycle targets;
/// the pose characteristics (AP, RP, vAP, AD, RD) of measured cycles (validate/iso9283.hpp).

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <memory>

#include "cli_common.hpp"
#include "command_registry.hpp"
#include "robcal/core/units.hpp"
#include "robcal/report/report.hpp"
#include "robcal/validate/test_workflows.hpp"

namespace robcal::cli {
namespace {

struct Iso9283PlanOptions {
  Iso9283PlanFilesRequest request;
  std::string region, orientation = "0,0,1,0", config = "front-up-noflip";
  bool json = false;
};

struct AnalyseOptions {
  std::string poses, measurements;
  int min_cycles = kIso9283Cycles;
  bool json = false;
};

void run_iso9283_plan(Iso9283PlanOptions o) {
  Iso9283PlanRequest& request = o.request.test;
  const std::vector<double> box = parse_numbers(o.region, 6, "--region");
  request.region_min_mm = Eigen::Vector3d(box[0], box[1], box[2]);
  request.region_max_mm = Eigen::Vector3d(box[3], box[4], box[5]);
  request.world_R_tcp = parse_orientation(o.orientation, "--orientation");
  request.config = parse_config(o.config);
  const Iso9283PlanFiles result = iso9283_plan_files(o.request);
  const Iso9283Plan& plan = result.plan;
  if (o.json) {
    print_json(iso9283_plan_json(result));
    return;
  }
  fmt::print(
      "ISO 9283 test cube for {} ({} model): edge {:.3f} mm, centre ({:.3f}, {:.3f}, {:.3f}) "
      "mm; poses on the plane C1-C2-C7-C8, configuration {}\n",
      result.test.robot.model.name, result.test.robot.level, plan.cube_edge_mm,
      plan.cube_centre_mm.x(), plan.cube_centre_mm.y(), plan.cube_centre_mm.z(),
      result.test.config.label());
  fmt::print(
      "  pose          x          y          z |      J1       J2       J3       J4       "
      "J5       J6 (deg)\n");
  for (const Iso9283PlannedPose& p : plan.poses) {
    fmt::print("  {:<4} {:>10.3f} {:>10.3f} {:>10.3f} |", p.name, p.world_T_tcp.p.x(),
               p.world_T_tcp.p.y(), p.world_T_tcp.p.z());
    for (int j = 0; j < kJointCount; ++j) fmt::print(" {:>8.3f}", rad2deg(p.joints[j]));
    fmt::print("\n");
  }
  fmt::print("{} cycles P1 → P5 → P4 → P3 → P2 (ISO 9283 pose accuracy and repeatability)\n",
             result.test.cycles);
  if (!plan.vap_sequence.empty())
    fmt::print(
        "multi-directional test (vAP): every pose approached along world +x, +y, +z from {:g} mm "
        "back, {} cycles per direction; measure with direction 1..3 in the measurements file; "
        "readings at the pre-poses (\"-from\") are not part of the test\n",
        result.test.vap_approach_mm, result.test.cycles);
  fmt::print("wrote {}\n", fmt::join(result.files, ", "));
}

void run_analyse(const AnalyseOptions& o) {
  const Iso9283Result r = iso9283_analyse_files(o.poses, o.measurements, o.min_cycles);
  if (o.json) {
    nlohmann::json out = iso9283_json(r);
    out["measurements"] = o.measurements;
    out["min_cycles"] = o.min_cycles;
    print_json(out);
    return;
  }
  fmt::print("ISO 9283 pose characteristics from {} (commanded poses {})\n", o.measurements,
             o.poses);
  if (o.min_cycles < kIso9283Cycles)
    fmt::print("note: fewer than the standard's {} cycles accepted (--min-cycles {})\n",
               kIso9283Cycles, o.min_cycles);
  fmt::print(
      "  pose cycles    AP (mm)    RP (mm)   vAP (mm) |  AP a/b/c (deg)             RP ±a/b/c "
      "(deg)\n");
  for (const Iso9283PoseFigures& f : r.poses) {
    fmt::print("  P{}   {:>6} {:>10.4f} {:>10.4f} {:>10} |", f.pose, f.cycles, f.ap_mm, f.rp_mm,
               f.vap_mm ? fmt::format("{:.4f}", *f.vap_mm) : std::string("–"));
    if (f.has_orientation)
      fmt::print(" {:+.4f} {:+.4f} {:+.4f}   {:.4f} {:.4f} {:.4f}", f.ap_abc_deg.x(),
                 f.ap_abc_deg.y(), f.ap_abc_deg.z(), f.rp_abc_deg.x(), f.rp_abc_deg.y(),
                 f.rp_abc_deg.z());
    else
      fmt::print(" no orientation measured");
    fmt::print("\n");
  }
  if (r.distance) {
    const Iso9283DistanceFigures& d = *r.distance;
    fmt::print(
        "distance P2-P4 (clause 7.3): commanded {:.4f} mm, AD {:+.4f} mm, RD ±{:.4f} mm over "
        "{} cycles\n",
        d.commanded_mm, d.ad_mm, d.rd_mm, d.cycles);
    if (d.has_orientation)
      fmt::print(
          "  orientation AD a/b/c {:+.4f} {:+.4f} {:+.4f} deg, RD ±{:.4f} ±{:.4f} ±{:.4f} deg\n",
          d.ad_abc_deg.x(), d.ad_abc_deg.y(), d.ad_abc_deg.z(), d.rd_abc_deg.x(), d.rd_abc_deg.y(),
          d.rd_abc_deg.z());
  } else {
    fmt::print("distance figures need P2 and P4 measured in the same cycles\n");
  }
}

const bool iso9283_registered = register_command(65, [](CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "iso9283", "ISO 9283 pose accuracy and repeatability: plan the test cube, analyse cycles");
  cmd->require_subcommand(1);
  auto plan = std::make_shared<Iso9283PlanOptions>();
  auto* p = cmd->add_subcommand(
      "plan",
      "The test cube in a workspace region, its poses P1-P5 and the joint targets of the "
      "cycles (compensation IK of the model)");
  p->add_option("--robot", plan->request.robot, "Built-in robot name or robot file")->required();
  p->add_option("--tool", plan->request.tool, "Tool file (its TCP); default: the flange");
  p->add_option("--model", plan->request.model,
                "Calibrated model (joint targets compensated); default: the nominal robot, base "
                "at the origin");
  p->add_option("--region", plan->region,
                "Workspace region (world frame, mm): xmin,ymin,zmin,xmax,ymax,zmax")
      ->required();
  p->add_option("--orientation", plan->orientation,
                "TCP orientation at every pose, quaternion qw,qx,qy,qz (world)")
      ->capture_default_str();
  p->add_option("--config", plan->config, "Arm configuration")->capture_default_str();
  p->add_option("--cycles", plan->request.test.cycles, "Cycles (the standard: 30)")
      ->capture_default_str();
  p->add_option("--out-poses", plan->request.out_poses, "Pose-list CSV of P1-P5")
      ->capture_default_str();
  p->add_option("--out-cycles", plan->request.out_cycles,
                "Joint targets of every move (CSV, degrees)")
      ->capture_default_str();
  p->add_option("--vap-approach", plan->request.test.vap_approach_mm,
                "Also plan the multi-directional test (vAP): approach distance along world +x, "
                "+y, +z (mm); 0: none")
      ->capture_default_str();
  p->add_option("--out-vap-cycles", plan->request.out_vap_cycles,
                "Joint targets of the multi-directional test's moves (CSV, degrees)")
      ->capture_default_str();
  p->add_option("--program", plan->request.program,
                "Also write the cycles as robot programs (programs layer): rapid, krl, ls, "
                "urscript");
  p->add_option("--program-dir", plan->request.program_dir, "Folder for the programs")
      ->capture_default_str();
  p->add_flag("--json", plan->json, "Machine-readable output");
  p->callback([plan] { run_iso9283_plan(*plan); });

  auto analyse = std::make_shared<AnalyseOptions>();
  auto* a = cmd->add_subcommand("analyse",
                                "AP, RP (position, orientation), vAP, AD, RD of measured cycles");
  a->add_option("--poses", analyse->poses, "The commanded poses (pose list from `plan`)")
      ->required();
  a->add_option("--measurements", analyse->measurements,
                "Measured cycles: pose,cycle,x,y,z[,qw,qx,qy,qz][,direction] (mm)")
      ->required();
  a->add_option("--min-cycles", analyse->min_cycles,
                "Fewest cycles accepted per pose (the standard: 30; at least 2)")
      ->capture_default_str();
  a->add_flag("--json", analyse->json, "Machine-readable output");
  a->callback([analyse] { run_analyse(*analyse); });
});

}  // namespace
}  // namespace robcal::cli
