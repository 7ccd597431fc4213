#pragma once
// Joint properties used by the joint tests: the paper's Brazilian-disc rock (§2.1:
// E = 21 GPa, ft = 2.5 MPa, GI = 120 N/m, c = 20 MPa, phi = 45 deg, GII = 1500 N/m)
// with the FDEM penalty kn = ks = p*E/h, p = 10, h = 5 mm (docs/theory.md §3).
#include "model/joints.hpp"

namespace dsdem::test {

inline JointProperties disc_rock() {
  JointProperties p;
  p.name = "disc_rock";
  p.kn = 10.0 * 21e9 / 5e-3;  // 4.2e13 Pa/m
  p.ks = p.kn;
  p.ft = 2.5e6;
  p.c = 20e6;
  p.phi = 45.0 * kPi / 180.0;
  p.GI = 120.0;
  p.GII = 1500.0;
  return p;
}

}  // namespace dsdem::test
