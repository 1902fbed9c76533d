// substrate_light/wc18 — WC18 §4.2 eq. 5: Id = 1 - (1 - L.(r N)) ds, MNPR's light
// L = (sin t, cos t, tilt / 89), N = (-r (tex.r - 0.5), -r (tex.g - 0.5), 1); output C * Id.
//@pass light out=4 in=color,paper
#define SQUARED 0
//@include substrate_light_common.glsl
