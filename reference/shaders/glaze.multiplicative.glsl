// glaze/multiplicative — LD06 §4.2 glazing (spec §4.7): starting from the picture (or the paper colour
// when there is none), layers 0..3 back to front, each its ramp colour at opacity
// sat(ramp alpha x wash amount); multiplicative: dst (1 - k (1 - c)). Ramps resampled bilinearly.
//@pass glaze out=4 size=wash in=color,wash,ramp0:linear,ramp1:linear,ramp2:linear,ramp3:linear
#define MUL true
//@include glaze_common.glsl
