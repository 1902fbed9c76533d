// glaze/over — LD06 §4.2 glazing (spec §4.7): starting from the picture (or the paper colour
// when there is none), layers 0..3 back to front, each its ramp colour at opacity
// sat(ramp alpha x wash amount); over: mix(dst, c, k). Ramps resampled bilinearly.
//@pass glaze out=4 size=wash in=color,wash,ramp0:linear,ramp1:linear,ramp2:linear,ramp3:linear
#define MUL false
//@include glaze_common.glsl
