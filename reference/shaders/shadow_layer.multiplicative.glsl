// shadow_layer/multiplicative — LD06 §3.3: the shadow intensity map as a wash (Gaussian blur H, V at its
// own size; resampled; smoothstep, edge, paper: ld06_wash.glsl, edge multiplicative, paper before)
// in the shadow colour at opacity sat(alpha x amount), glazed multiplicatively onto the picture.
//@pass h out=1 in=shadow
//@pass v out=1 in=h
//@pass layer out=4 size=color in=color,shadow:linear,v:linear,paper
//@output color=layer
#define MUL true
//@include shadow_layer_common.glsl
