// Pinocchio's constraintDynamics timed in C++: the peer of the `forward_dynamics_runtime`
// benches. Built and run by python/bench_pinocchio_cpp.py, which writes the model as text (the
// exported MJCF as Pinocchio's own parser reads it: joints, placements, inertias, the loops'
// constraints, one state and Pinocchio's accelerations there); this builds the same model in
// code, checks its accelerations against Python's, and times the call.
//
// Header-only, on purpose: nothing of the `pin` wheel's compiled libraries is called. Built with
// `-march=native`, the wheel's MJCF parser crashed (its Eigen objects laid out for another
// instruction set); templates instantiated here share one layout.
#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/constrained-dynamics.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace pin = pinocchio;

static pin::SE3 read_placement(std::istream& in) {
  Eigen::Matrix3d r;
  Eigen::Vector3d p;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) in >> r(i, j);
  in >> p[0] >> p[1] >> p[2];
  return pin::SE3(r, p);
}

static Eigen::Vector3d read3(std::istream& in) {
  Eigen::Vector3d v;
  in >> v[0] >> v[1] >> v[2];
  return v;
}

static pin::JointModel read_joint(std::istream& in) {
  std::string kind;
  in >> kind;
  if (kind == "composite") {
    int n;
    in >> n;
    pin::JointModelComposite composite;
    for (int k = 0; k < n; ++k) {
      pin::JointModel part = read_joint(in);
      composite.addJoint(part, read_placement(in));
    }
    return composite;
  }
  if (kind == "RX") return pin::JointModelRX();
  if (kind == "RY") return pin::JointModelRY();
  if (kind == "RZ") return pin::JointModelRZ();
  if (kind == "PX") return pin::JointModelPX();
  if (kind == "PY") return pin::JointModelPY();
  if (kind == "PZ") return pin::JointModelPZ();
  if (kind == "Ru") return pin::JointModelRevoluteUnaligned(read3(in));
  if (kind == "Pu") return pin::JointModelPrismaticUnaligned(read3(in));
  if (kind == "S") return pin::JointModelSpherical();
  if (kind == "F") return pin::JointModelFreeFlyer();
  throw std::runtime_error("unknown joint " + kind);
}

static Eigen::VectorXd read_vector(std::istream& in) {
  std::vector<double> values;
  double x;
  while (in >> x) values.push_back(x);
  return Eigen::Map<Eigen::VectorXd>(values.data(), values.size());
}

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s model.txt\n", argv[0]);
    return 2;
  }
  std::ifstream file(argv[1]);
  pin::Model model;
  PINOCCHIO_STD_VECTOR_WITH_EIGEN_ALLOCATOR(pin::RigidConstraintModel) constraints;
  pin::ProximalSettings settings(1e-14, 0.0, 1);
  Eigen::VectorXd q, v, tau, want;
  std::string line;
  int joints = 0;
  while (std::getline(file, line)) {
    std::istringstream in(line);
    std::string key;
    in >> key;
    if (key == "gravity") {
      model.gravity.linear(read3(in));
    } else if (key == "joint") {
      pin::JointIndex parent;
      in >> parent;
      pin::SE3 placement = read_placement(in);
      double mass;
      in >> mass;
      Eigen::Vector3d lever = read3(in);
      Eigen::Matrix3d inertia;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) in >> inertia(i, j);
      pin::JointModel joint = read_joint(in);
      pin::JointIndex id =
          model.addJoint(parent, joint, placement, "joint" + std::to_string(++joints));
      model.appendBodyToJoint(id, pin::Inertia(mass, lever, inertia), pin::SE3::Identity());
    } else if (key == "constraint") {
      int kind;
      pin::JointIndex one, two;
      in >> kind >> one >> two;
      pin::SE3 p1 = read_placement(in);
      pin::SE3 p2 = read_placement(in);
      constraints.emplace_back(kind == 3 ? pin::CONTACT_3D : pin::CONTACT_6D, model, one, p1, two,
                               p2, pin::LOCAL);
    } else if (key == "settings") {
      double mu;
      int iterations;
      in >> mu >> iterations;
      settings = pin::ProximalSettings(1e-14, mu, iterations);
    } else if (key == "q") {
      q = read_vector(in);
    } else if (key == "v") {
      v = read_vector(in);
    } else if (key == "tau") {
      tau = read_vector(in);
    } else if (key == "ddq") {
      want = read_vector(in);
    }
  }
  pin::Data data(model);
  PINOCCHIO_STD_VECTOR_WITH_EIGEN_ALLOCATOR(pin::RigidConstraintData) datas;
  for (const auto& c : constraints) datas.emplace_back(c);
  pin::initConstraintDynamics(model, data, constraints, datas);
  Eigen::VectorXd ddq = pin::constraintDynamics(model, data, q, v, tau, constraints, datas, settings);
  double error = (ddq - want).cwiseAbs().maxCoeff() / want.cwiseAbs().maxCoeff();
  const int calls = 20000;
  std::vector<double> runs;
  for (int r = 0; r < 11; ++r) {
    auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < calls; ++k) {
      pin::constraintDynamics(model, data, q, v, tau, constraints, datas, settings);
    }
    auto end = std::chrono::steady_clock::now();
    runs.push_back(std::chrono::duration<double, std::micro>(end - start).count() / calls);
  }
  std::sort(runs.begin(), runs.end());
  std::printf("{\"file\": \"%s\", \"median_us\": %.4f, \"min_us\": %.4f, \"max_us\": %.4f, "
              "\"relative_difference_from_python\": %.3g, \"nq\": %d, \"nv\": %d, \"runs_us\": [",
              argv[1], runs[5], runs[0], runs[10], error, (int)model.nq, (int)model.nv);
  for (std::size_t r = 0; r < runs.size(); ++r) std::printf("%s%.4f", r ? ", " : "", runs[r]);
  std::printf("]}\n");
  return error < 1e-9 ? 0 : 1;
}
