// Dr2 rock slope: SENSITIVITY CASE "gentle lower slope" (docs/dr2.md §4, "Sensitivity to
// the lower-slope geometry (alternative profile)"). NOT a replacement of ../dr2.geo: the
// main scenarios keep docs/dr2.md §1's reconstructed profile. This file is ../dr2.geo with
// ONLY the lower slope below the slope toe (560, 900), deposit III's base below
// (590, 850), the river bed, the left bank (moved right) and the model width changed.
//
// Why: on the reconstructed profile the lower slope is 42.7 deg (560,900)-(690,780) and
// 49 deg (690,780)-(720,745), and deposit III's base 52/50/37 deg. A block stops on a
// 42.7 deg face only with friction >= tan 42.7 = 0.92, above the documented run-out range
// (0.55-0.85), so every debris that leaves the bench reaches the river and deposit III
// slides off its 50 deg base (docs/dr2.md §3). This case tests that explanation directly:
// the same slope, the same materials, on a gentler lower slope.
//
// Choice (a plausible valley side with a colluvium apron; the paper's real section is
// in its figures, not in its text):
//   * ground below the slope toe (deposit III surface), concave like a talus/colluvium
//     apron that flattens toward the river:
//       (560, 900) -> (700, 825) 28.2 deg -> (800, 770) 28.8 deg -> (860, 745) 22.6 deg
//     i.e. 27.3 deg on average from the slope toe to the river bed (reconstruction:
//     42.7-49 deg, 44.3 deg on average); 28 deg is a typical slope of a colluvium apron,
//     below the 34-40 deg repose angle of coarse debris, so it is not oversteepened.
//   * deposit III base: (540, 914) (547.03, 905) (565, 882) (590, 850) unchanged (the
//     mudstone block and the T1y3 contact layer are untouched; 52 deg over its upper
//     40 m as before), then (590, 850) -> (700, 797) 25.7 deg -> (800, 752) 24.2 deg ->
//     (840, 745) 9.9 deg (the toe, on the river terrace). Vertical thickness 11-34 m
//     (reconstruction: 12-36 m; docs/dr2.md §1: 20-35 m in its middle).
//   * river bed at the same 745 m and the same 90 m width, moved 140 m outward:
//     x = 860-950 m (was 720-810); the left bank is the original one shifted right by
//     140 m: (1020, 860) (1120, 1040), and the model is widened from 1298 to 1450 m (the
//     right boundary at x = 1450 m, the top corner at (1450, 1169): the last 330 m of the
//     left bank rise at 21.3 deg instead of 22.1 deg). Not 1438 m (= 1298 + 140): with
//     1438 m the base is meshed with a node at x = 143.8 m (h = 8 and 12 m) that has no
//     other node within half a mean element width above it, and dsdem's free-field
//     column height for it (highest node within h_mean/2 of its x,
//     src/boundary/boundary_setup.cpp) comes out 0: the run stops ("free field: column
//     height H must be positive, got 0"). 1450 m meshes without that at h = 4, 8, 12, 16 m.
//     The base of the contact band under the lower slope and the left bank follows:
//     (600, 760) (760, 680) (970, 680) (1140, 900) (1450, 1000).
//   * the water intake stays at the right-bank foot, on the ground, at the same
//     elevation (750.83 m, 5.83 m over the bed) and 14 m from the river's edge:
//     (846, 750.8333) (was (715, 750.8333), 5 m from the edge of a 49 deg face).
// Everything else is identical to ../dr2.geo: the ground above (560, 900) and all of it
// above 960 m, the column, the plate, L1-L3, J1-J4, the mudstone block, the T1y3 and
// T1m1/T1m2 back rock, the physical-group names, the boundaries' names, the mesh grading.
// Mesh (gmsh 4.8.4, -clmax h): h = 12 m 1393 triangles (dr2.geo: 1239), 8 m 2858 (2475), 4 m
// 10080 (8618); the extra ones are in the longer deposit III (147 triangles at 12 m, was
// 95) and the wider bedrock; plate, column and mudstone have the same triangle counts as
// in dr2.geo at h = 4, 8, 12 m (298/331/1936, 82/95/505, 36/47/240).
// Post-processing: scripts/dr2_postprocess.py OUT --geometry examples/dr2/sensitivity/dr2_gentle.json
// (river bed, channel, intake and ground of this profile).
//
// ---------------------------------------------------------------------------------------
// The header of ../dr2.geo follows (its geometry notes apply above the slope toe).
//
// Dr2 rock slope, Suofengying hydropower station (Wujiang river, Guizhou): the
// reconstructed 2D profile of docs/dr2.md §1. x toward the river (m), y = elevation (m).
//
// The paper (Mao Jia et al. 2026) gives no coordinates; this profile is rebuilt from the
// numbers it does give: model 1298 m wide, up to 689 m tall (base at 480 m); crest
// ~1080 m at the persistent tension crack L1; a 5-10 deg T1m2 dolomite platform above
// 1070 m; a ~70 deg T1m1 limestone cliff 960-1074 m; the 180 m dangerous column, 29-37 m
// thick, cut by L1 (back), L3 (11-22 m thin outer plate) and L2 (partial); soft T1y3
// mudstone under the column with weak interlayers J1 (960 m) and J2-J4 (945, 925, 905 m
// at the face) dipping ~3 deg out of the slope; deposit No. III (20-35 m thick
// colluvium) on the lower slope down to the river; the river bed at 745 m and the
// opposite (left) bank.
//
// Small deviations from docs/dr2.md §1 (all < 2 m), so that curves meet exactly:
//   * J1 carries the 3 deg dip all along: z = 960 + (474 - x) tan 3deg, so L1 ends at
//     (441, 961.73) and L3 at (452, 961.15) on J1 instead of at z = 960;
//   * L3 starts on the ground line at (425, 1075.74) (docs/dr2.md §1: 1075);
//   * the lower tip of L2 is at (435, 1000), midway between L1 and L3 (docs/dr2.md §1: 440,
//     only 2.9 m from L3, which forced 1.8 m slivers and a 2x smaller time step);
//   * J4 (905 m) reaches the face under deposit III, so it ends on the deposit base at
//     (547.03, 905).
//
// Mesh size: the scenario's mesh.element_size h (dsdem passes it as gmsh -clmax) is the
// size in the breakable zone A. The file reads h, lifts the global cap and grades the
// mesh: 2.5 h in the contact band (zone C), 12 h in the deep bedrock (zone B).
// h = 4 m gives about 8.6k elements (the paper: 8951-9288); h = 8 m about 2.5k.
//
// Physical groups
//   surfaces : column   T1m1 limestone between L1 and L3 (zone A, breakable)
//              plate    T1m1 limestone outside L3, the thin plate (zone A)
//              mudstone T1y3 mudstone + marl under the column, with J1-J4 (zone A)
//              deposit  deposit No. III colluvium (zone A)
//              T1m2     dolomite platform behind L1 above 1070 m (zone C)
//              T1m1     limestone behind L1, 1070 m down to the J1 horizon (zone C)
//              T1y3     mudstone behind/below the breakable mudstone (zone C)
//              bedrock_surface  bedrock band under deposit III, river bed, left bank (zone C)
//              bedrock  deep bedrock (zone B, plain FEM)
//   curves   : L1 L2 L3 (cracks), J1_plate J1_column J1_back (= interlayer J1), J2 J3 J4
//              (interlayers), left right base
//              (truncated boundaries), ground (free surface), river (river bed, 720-810 m)
//   points   : intake (water intake at the right-bank foot), g_front, g_foot, g_top_back,
//              g_top_front (reference gauge positions; the scenarios may move them)

h = Mesh.CharacteristicLengthMax;      // = mesh.element_size given by the scenario
If (h > 1e3)
  h = 3.5;                             // gmsh run by hand without -clmax
EndIf
Mesh.CharacteristicLengthMax = 1e22;   // local sizes below govern
Mesh.MeshSizeExtendFromBoundary = 1;
hA = h;          // breakable zone A
hC = 2.5 * h;    // contact band, zone C
hB = 12 * h;     // deep bedrock, zone B
t3 = Tan(3 * Pi / 180);                // 3 deg outward dip of J1-J4

// ---- ground surface, right bank to left bank
Point(1)  = {0, 1128, 0, hB};
Point(2)  = {250, 1102, 0, hC};
Point(3)  = {398, 1080, 0, hA};        // crest, top of L1
Point(4)  = {417, 1077, 0, hA};        // top of L2
Point(5)  = {425, 1075.7368, 0, hA};   // top of L3
Point(6)  = {436, 1074, 0, hA};        // cliff edge
Point(7)  = {474, 960, 0, hA};         // cliff toe = J1 at the face
Point(8)  = {495.5217, 945, 0, hA};    // J2 at the face
Point(9)  = {524.2174, 925, 0, hA};    // J3 at the face
Point(10) = {540, 914, 0, hA};         // upper edge of deposit III
Point(11) = {560, 900, 0, hA};         // slope toe
Point(12) = {700, 825, 0, hA};         // gentle: was (690, 780)
Point(18) = {800, 770, 0, hA};         // gentle: new ground point
Point(13) = {860, 745, 0, hA};         // river bed, right edge (toe of deposit III); was x = 720
Point(14) = {950, 745, 0, hC};         // river bed, left edge; was x = 810
Point(15) = {1020, 860, 0, hC};        // left bank + 140 m
Point(16) = {1120, 1040, 0, hC};       // left bank + 140 m
Point(17) = {1450, 1169, 0, hB};       // left bank + 140 m, right edge at 1450 (model 1450 m wide, see top)
// ---- cracks and interlayers
Point(20) = {441, 960 + 33 * t3, 0, hA};    // L1 on J1
Point(21) = {452, 960 + 22 * t3, 0, hA};    // L3 on J1
Point(22) = {435, 1000, 0, hA};             // lower tip of L2, midway between L1 and L3
Point(23) = {360, 960 + 114 * t3, 0, hA};   // back end of the breakable J1
Point(24) = {360, 945 + 135.5217 * t3, 0, hA}; // J2 back end
Point(25) = {360, 925 + 164.2174 * t3, 0, hA}; // J3 back end
Point(26) = {547.0313, 905, 0, hA};         // J4 on the deposit base
Point(27) = {360, 905 + 187.0313 * t3, 0, hA}; // J4 back end
Point(28) = {565, 882, 0, hA};              // deposit base / mudstone bottom
Point(29) = {360, 882 + 205 * t3, 0, hA};   // mudstone block, back bottom corner
// ---- deposit III base
Point(30) = {590, 850, 0, hA};
Point(31) = {700, 797, 0, hA};              // gentle: was (640, 790)
Point(32) = {800, 752, 0, hA};              // gentle: was (700, 745)
Point(33) = {840, 745, 0, hA};              // gentle: toe of the base
// ---- layer boundaries in the back rock
Point(40) = {0, 960 + 474 * t3, 0, hB};     // J1 horizon (T1m1 / T1y3) at the left side
Point(41) = {0, 1070, 0, hB};               // T1m2 / T1m1 at the left side
Point(42) = {398 + 10 * 43 / (1080 - 960 - 33 * t3), 1070, 0, hA}; // 1070 m on L1
Point(43) = {0, 900, 0, hB};                // base of the T1y3 contact layer
Point(44) = {0, 820, 0, hB};                // base of the contact band
Point(45) = {600, 760, 0, hC};
Point(46) = {760, 680, 0, hC};              // gentle: was (700, 680)
Point(47) = {970, 680, 0, hC};              // + 140 m
Point(48) = {1140, 900, 0, hC};             // + 140 m
Point(49) = {1450, 1000, 0, hB};            // right edge at 1450
Point(50) = {0, 480, 0, hB};
Point(51) = {1450, 480, 0, hB};             // right edge at 1450
// ---- named points
Point(60) = {846, 750.8333, 0, hA};         // water intake, right-bank foot (on the ground); gentle: was x = 715

// ---- lines
// ground
Line(1) = {1, 2};  Line(2) = {2, 3};  Line(3) = {3, 4};  Line(4) = {4, 5};
Line(5) = {5, 6};  Line(6) = {6, 7};  Line(7) = {7, 8};  Line(8) = {8, 9};
Line(9) = {9, 10}; Line(10) = {10, 11}; Line(11) = {11, 12}; Line(12) = {12, 18}; Line(18) = {18, 60};  // gentle: Line(18) added
Line(13) = {60, 13}; Line(14) = {13, 14}; Line(15) = {14, 15}; Line(16) = {15, 16};
Line(17) = {16, 17};
// L1 (split at 1070 m), L3, L2
Line(20) = {3, 42}; Line(21) = {42, 20};
Line(22) = {5, 21};
Line(23) = {4, 22};
// J1: under the plate, under the column, behind L1 (still breakable mudstone below)
Line(24) = {7, 21}; Line(25) = {21, 20}; Line(26) = {20, 23};
// J2, J3, J4
Line(27) = {8, 24}; Line(28) = {9, 25}; Line(29) = {26, 27};
// mudstone block: back side (x = 360) and bottom
Line(30) = {23, 24}; Line(31) = {24, 25}; Line(32) = {25, 27}; Line(33) = {27, 29};
Line(34) = {29, 28};
// deposit base
Line(35) = {10, 26}; Line(36) = {26, 28}; Line(37) = {28, 30}; Line(38) = {30, 31};
Line(39) = {31, 32}; Line(40) = {32, 33}; Line(19) = {33, 13};  // gentle: Line(19) added
// back rock layers
Line(41) = {23, 40};        // J1 horizon behind the breakable block (T1m1 / T1y3)
Line(42) = {41, 42};        // 1070 m
Line(43) = {30, 43};        // base of the T1y3 contact layer
// left side
Line(44) = {50, 44}; Line(45) = {44, 43}; Line(46) = {43, 40}; Line(47) = {40, 41};
Line(48) = {41, 1};
// contact band base, right side, model base
Line(49) = {44, 45}; Line(50) = {45, 46}; Line(51) = {46, 47}; Line(52) = {47, 48};
Line(53) = {48, 49};
Line(54) = {51, 49}; Line(55) = {49, 17};
Line(56) = {50, 51};

// ---- surfaces
Curve Loop(1) = {22, -24, -6, -5};                 // plate: L3, J1, face, ground
Plane Surface(1) = {1};
Curve Loop(2) = {20, 21, -25, -22, -4, -3};        // column: L1, J1, L3, ground
Plane Surface(2) = {2};
Curve{23} In Surface{2};                           // L2 ends inside the column
Curve Loop(3) = {24, 25, 26, 30, -27, -7};         // mudstone upper slab (J1 - J2)
Plane Surface(3) = {3};
Curve Loop(4) = {27, 31, -28, -8};                 // J2 - J3
Plane Surface(4) = {4};
Curve Loop(5) = {28, 32, -29, -35, -9};            // J3 - J4
Plane Surface(5) = {5};
Curve Loop(6) = {29, 33, 34, -36};                 // below J4
Plane Surface(6) = {6};
Curve Loop(7) = {10, 11, 12, 18, 13, -19, -40, -39, -38, -37, -36, -35}; // deposit III
Plane Surface(7) = {7};
Curve Loop(8) = {1, 2, 20, -42, 48};               // T1m2 platform
Plane Surface(8) = {8};
Curve Loop(9) = {42, 21, 26, 41, 47};              // T1m1 back rock
Plane Surface(9) = {9};
Curve Loop(10) = {-41, 30, 31, 32, 33, 34, 37, 43, 46}; // T1y3 contact layer
Plane Surface(10) = {10};
Curve Loop(11) = {-43, 38, 39, 40, 19, 14, 15, 16, 17, -55, -53, -52, -51, -50, -49, 45};
Plane Surface(11) = {11};                          // bedrock surface band
Curve Loop(12) = {56, 54, -53, -52, -51, -50, -49, -44};
Plane Surface(12) = {12};                          // deep bedrock

Physical Surface("plate") = {1};
Physical Surface("column") = {2};
Physical Surface("mudstone") = {3, 4, 5, 6};
Physical Surface("deposit") = {7};
Physical Surface("T1m2") = {8};
Physical Surface("T1m1") = {9};
Physical Surface("T1y3") = {10};
Physical Surface("bedrock_surface") = {11};
Physical Surface("bedrock") = {12};

Physical Curve("L1") = {20, 21};
Physical Curve("L2") = {23};
Physical Curve("L3") = {22};
// J1 in three named parts, so that a scenario can weaken it under the plate only
Physical Curve("J1_plate") = {24};     // under the thin plate (x 452-474)
Physical Curve("J1_column") = {25};    // under the column between L1 and L3 (x 441-452)
Physical Curve("J1_back") = {26};      // behind L1, top of the breakable mudstone (x 360-441)
Physical Curve("J2") = {27};
Physical Curve("J3") = {28};
Physical Curve("J4") = {29};
Physical Curve("left") = {44, 45, 46, 47, 48};
Physical Curve("right") = {54, 55};
Physical Curve("base") = {56};
Physical Curve("ground") = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 18, 13, 14, 15, 16, 17};
Physical Curve("river") = {14};
Physical Point("intake") = {60};
