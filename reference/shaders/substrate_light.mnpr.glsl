// substrate_light/mnpr — MNPR substrateLighting: Id = 1 - (1 - N.L)^2 ds (spec §4.10), otherwise
// as substrate_light/wc18.
//@pass light out=4 in=color,paper
#define SQUARED 1
//@include substrate_light_common.glsl
