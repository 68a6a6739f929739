// Pinocchio's C++ on the whole tree, the protocol of `benches/tree.rs`: every frame's pose
// (forwardKinematics + updateFramePlacements) and one frame's world-aligned Jacobian
// (computeFrameJacobian(..., LOCAL_WORLD_ALIGNED)), in ns per call: the minimum over 30 rounds of
// 20,000 calls on 256 random configurations (pinocchio::randomConfiguration), one thread. Also
// the one frame's pose alone (forwardKinematics + updateFramePlacement of that frame:
// `tip_fk_ns`), the single call that `benches/batch_kernels.rs` times for an arm's tip.
//
// Built and run by run_pinocchio.sh (header-compiled with -O3 -march=native, no Pinocchio
// shared library: see there). Usage: pinocchio_tree URDF FRAME
#include <pinocchio/multibody.hpp>
#include <pinocchio/parsers/urdf.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/aba.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

int main(int argc, char **argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s URDF FRAME\n", argv[0]);
    return 2;
  }
  pinocchio::Model model;
  pinocchio::urdf::buildModel(argv[1], model);
  pinocchio::Data data(model);
  const std::string frame = argv[2];
  if (!model.existFrame(frame)) {
    std::fprintf(stderr, "%s: no frame %s\n", argv[1], frame.c_str());
    return 2;
  }
  const auto fid = model.getFrameId(frame);
  std::vector<Eigen::VectorXd> qs;
  std::srand(1);
  for (int k = 0; k < 256; ++k) qs.push_back(pinocchio::randomConfiguration(model));
  pinocchio::Data::Matrix6x J(6, model.nv);
  J.setZero();
  using clock = std::chrono::steady_clock;
  const int calls = 20000;
  double best_fk = std::numeric_limits<double>::infinity();
  double best_j = best_fk;
  double best_tip = best_fk;
  volatile double sink = 0.0;
  for (int round = 0; round < 30; ++round) {
    const auto t0 = clock::now();
    for (int k = 0; k < calls; ++k) {
      pinocchio::forwardKinematics(model, data, qs[k % 256]);
      pinocchio::updateFramePlacements(model, data);
      sink = data.oMf[fid].translation()[0];
    }
    const auto t1 = clock::now();
    for (int k = 0; k < calls; ++k) {
      pinocchio::computeFrameJacobian(model, data, qs[k % 256], fid,
                                      pinocchio::LOCAL_WORLD_ALIGNED, J);
      sink = J(0, 0);
    }
    const auto t2 = clock::now();
    for (int k = 0; k < calls; ++k) {
      pinocchio::forwardKinematics(model, data, qs[k % 256]);
      sink = pinocchio::updateFramePlacement(model, data, fid).translation()[0];
    }
    const auto t3 = clock::now();
    best_fk = std::min(best_fk, std::chrono::duration<double, std::nano>(t1 - t0).count() / calls);
    best_j = std::min(best_j, std::chrono::duration<double, std::nano>(t2 - t1).count() / calls);
    best_tip = std::min(best_tip, std::chrono::duration<double, std::nano>(t3 - t2).count() / calls);
  }
  // Dynamics, the protocol of benches/tree.rs's dynamics_calls: v = 0.1, a (or tau) = 0.2.
  const Eigen::VectorXd v = Eigen::VectorXd::Constant(model.nv, 0.1);
  const Eigen::VectorXd a = Eigen::VectorXd::Constant(model.nv, 0.2);
  double best_dyn[4];
  std::fill(best_dyn, best_dyn + 4, std::numeric_limits<double>::infinity());
  for (int round = 0; round < 30; ++round) {
    auto t = clock::now();
    auto lap = [&](int k) {
      const auto now = clock::now();
      best_dyn[k] = std::min(best_dyn[k], std::chrono::duration<double, std::nano>(now - t).count() / calls);
      t = now;
    };
    for (int k = 0; k < calls; ++k) sink = pinocchio::rnea(model, data, qs[k % 256], v, a)[0];
    lap(0);
    for (int k = 0; k < calls; ++k) sink = pinocchio::computeGeneralizedGravity(model, data, qs[k % 256])[0];
    lap(1);
    for (int k = 0; k < calls; ++k) sink = pinocchio::crba(model, data, qs[k % 256])(0, 0);
    lap(2);
    for (int k = 0; k < calls; ++k) sink = pinocchio::aba(model, data, qs[k % 256], v, a)[0];
    lap(3);
  }
  std::printf("PINOCCHIO dynamics nv=%d rnea_ns=%.1f gravity_ns=%.1f crba_ns=%.1f aba_ns=%.1f\n",
              (int)model.nv, best_dyn[0], best_dyn[1], best_dyn[2], best_dyn[3]);
  (void)sink;
  std::printf("PINOCCHIO %s joints=%d frames=%zu nq=%d all_frames_fk_ns=%.1f frame_jacobian_ns=%.1f "
              "tip_fk_ns=%.1f\n",
              PINOCCHIO_VERSION, (int)model.njoints - 1, model.frames.size(), (int)model.nq,
              best_fk, best_j, best_tip);
  return 0;
}
