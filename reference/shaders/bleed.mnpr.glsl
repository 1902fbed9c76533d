// bleed/mnpr — MNPR colorBleeding: Algorithm 1 at full resolution, r = 10, sigma = 2r, a tap a
// is considered only when max(ctrl_d, ctrl_s) >= |a| / r; T = 0.0002 (MNPR gBleedingThreshold).
//@pass src out=4 size=half_if_half_res:color in=color:linear,ctrl_abstraction:linear
//@pass z out=1 size=half_if_half_res:color in=depth:linear
//@pass h out=4 in=src,z
//@pass v out=4 in=h,z
//@output bleed=v
#define BLEED_RULE 2
//@include bleed_common.glsl
