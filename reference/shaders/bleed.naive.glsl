// bleed/naive — WC16 (NPAR 2016 slides, "Color bleeding"): separable 21x21 Gaussian (sigma 20)
// of the whole colour image; alpha = the painted bleeding control (ctrl.abstraction.b).
//@pass src out=4 size=half_if_half_res:color in=color:linear,ctrl_abstraction:linear
//@pass h out=4 in=src
//@pass v out=4 in=h
//@output bleed=v
#define BLEED_RULE 0
//@include bleed_common.glsl
