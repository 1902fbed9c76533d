// bleed/joint_bilateral — WC17 §3.3 Algorithm 1: 21 taps, sigma 20, depth threshold T, the two
// rules; the H pass expands the control mask and the V pass uses it; half resolution by default.
//@pass src out=4 size=half_if_half_res:color in=color:linear,ctrl_abstraction:linear
//@pass z out=1 size=half_if_half_res:color in=depth:linear
//@pass h out=4 in=src,z
//@pass v out=4 in=h,z
//@output bleed=v
#define BLEED_RULE 1
//@include bleed_common.glsl
