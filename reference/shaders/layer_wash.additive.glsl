// layer_wash/additive — LD06 §3.1 (reconstructed, spec §4): per layer a Gaussian blur at the
// intensity maps' size (H then V), then at the paper's size (maps resampled bilinearly) the
// smoothstep shape, edge darkening (p = a + e) and paper border / granulation (ld06_wash.glsl).
//@pass h0 out=1 size=layer0 in=layer0
//@pass h1 out=1 size=layer0 in=layer1
//@pass h2 out=1 size=layer0 in=layer2
//@pass h3 out=1 size=layer0 in=layer3
//@pass v0 out=1 size=layer0 in=h0
//@pass v1 out=1 size=layer0 in=h1
//@pass v2 out=1 size=layer0 in=h2
//@pass v3 out=1 size=layer0 in=h3
//@pass wash out=4 size=paper in=layer0:linear,layer1:linear,layer2:linear,layer3:linear,v0:linear,v1:linear,v2:linear,v3:linear,paper
//@output wash=wash
#define ADDITIVE true
//@include layer_wash_common.glsl
