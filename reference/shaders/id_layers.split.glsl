// id_layers/split — LD06 §3.1: an ID map (1 + layer, 0 = background) split into four layer masks:
// layer k = round(id) - 1 - first; beyond first + 3 folded into the last when `fold`.
//@pass l0 out=1 in=ids
//@pass l1 out=1 in=ids
//@pass l2 out=1 in=ids
//@pass l3 out=1 in=ids
//@output layer0=l0
//@output layer1=l1
//@output layer2=l2
//@output layer3=l3

#if defined(PASS_l0)
const int K = 0;
#elif defined(PASS_l1)
const int K = 1;
#elif defined(PASS_l2)
const int K = 2;
#else
const int K = 3;
#endif
void main() {
    float v = fetch(s_ids, pixel()).r;
    int slot = -1;
    if (v >= 0.5 && v < 16777216.0) {
        int k = int(floor(v + 0.5)) - 1 - u_first;
        if (k >= 0 && k <= 3) slot = k;
        else if (k > 3 && u_fold) slot = 3;
    }
    o_color = vec4(slot == K ? 1.0 : 0.0);
}
