// tests/scenes/layers_test.cpp — LD06 §3.1 layers of a scene (scenes/layers.h; docs/ld06.md
// "Layers"): one layer per material in first-use order by default, the scene file's groups first,
// colours from the materials (textures averaged, masked texels skipped, linear colours encoded).
#include <gtest/gtest.h>

#include "core/color.h"
#include "scenes/layers.h"

namespace aq::scene {
namespace {

Scene three_objects() {
    Scene sc;
    for (const char* n : {"bark", "leaves", "flower"}) {
        Material m;
        m.name = n;
        sc.materials.push_back(m);
    }
    sc.materials[0].base_color = {0.4f, 0.3f, 0.2f, 1.0f};
    sc.materials[1].base_color = {0.2f, 0.6f, 0.1f, 1.0f};
    // meshes: trunk (bark), crown (leaves, then bark), bloom (flower)
    const int mats[3][2] = {{0, -1}, {1, 0}, {2, -1}};
    const char* names[3] = {"trunk", "crown", "bloom"};
    for (int i = 0; i < 3; ++i) {
        Mesh mesh;
        mesh.name = names[i];
        for (int k = 0; k < 2; ++k)
            if (mats[i][k] >= 0) {
                Primitive p;
                p.material = mats[i][k];
                mesh.primitives.push_back(p);
            }
        sc.meshes.push_back(mesh);
        Instance inst;
        inst.mesh = i;
        inst.object_id = std::uint32_t(i + 1);
        inst.name = std::string(names[i]) + "_node";
        sc.instances.push_back(inst);
    }
    return sc;
}

TEST(Layers, OneLayerPerMaterialInFirstUseOrder) {
    Scene sc = three_objects();
    std::swap(sc.instances[0], sc.instances[2]);  // instances: bloom, crown (leaves, bark), trunk
    const LayerTable t = build_layer_table(sc);
    ASSERT_EQ(t.layers.size(), 3u);
    EXPECT_EQ(t.layers[0].name, "flower");
    EXPECT_EQ(t.layers[1].name, "leaves");
    EXPECT_EQ(t.layers[2].name, "bark");
    EXPECT_EQ(t.of(2, 1), 1);  // crown's leaves
    EXPECT_EQ(t.of(2, 0), 2);  // crown's bark primitive and the trunk share the bark layer
    EXPECT_EQ(t.of(1, 0), 2);
    EXPECT_EQ(t.of(3, 2), 0);
    EXPECT_EQ(t.of(9, 0), -1);
    EXPECT_FLOAT_EQ(t.layers[2].color.r, 0.4f);  // display-valued material: as given
    EXPECT_FLOAT_EQ(t.layers[2].dark.r, 0.4f * kLayerDarkTone);
}

TEST(Layers, SceneFileGroupsComeFirstAndTheRestFollowByMaterial) {
    Scene sc = three_objects();
    LayerSpec g;
    g.name = "plant";
    g.meshes = {"crown"};
    g.nodes = {"bloom_node"};
    g.color = glm::vec3(0.1f, 0.2f, 0.3f);
    g.alpha = 0.5f;
    sc.layers.push_back(g);
    const LayerTable t = build_layer_table(sc);
    ASSERT_EQ(t.layers.size(), 2u);
    EXPECT_EQ(t.layers[0].name, "plant");
    EXPECT_EQ(t.of(2, 1), 0);
    EXPECT_EQ(t.of(2, 0), 0);  // the crown's bark primitive is in the crown's group
    EXPECT_EQ(t.of(3, 2), 0);
    EXPECT_EQ(t.of(1, 0), 1);  // the trunk is not in a group: its material's layer
    EXPECT_EQ(t.layers[1].name, "bark");
    EXPECT_FLOAT_EQ(t.layers[0].color.b, 0.3f);
    EXPECT_FLOAT_EQ(t.layers[0].dark.b, 0.3f * kLayerDarkTone);
    EXPECT_FLOAT_EQ(t.layers[0].alpha, 0.5f);
}

TEST(Layers, MaterialColourAveragesTheTextureOverUnmaskedTexels) {
    Scene sc = three_objects();
    Texture tex;
    tex.image = ImageF(4, 1, 4, 0.0f);
    for (int x = 0; x < 4; ++x) {
        tex.image.at(x, 0, 0) = x < 2 ? 0.2f : 0.9f;  // two leaf texels 0.2, two transparent ones 0.9
        tex.image.at(x, 0, 1) = 0.5f;
        tex.image.at(x, 0, 3) = x < 2 ? 1.0f : 0.0f;
    }
    sc.textures.push_back(tex);
    Material& m = sc.materials[1];
    m.base_color = {1.0f, 1.0f, 1.0f, 1.0f};
    m.base_color_texture.texture = 0;
    m.alpha_mode = AlphaMode::Mask;
    m.linear_color = true;
    const glm::vec3 c = material_display_color(sc, 1);
    EXPECT_FLOAT_EQ(c.r, linear_to_srgb(0.2f));
    EXPECT_FLOAT_EQ(c.g, linear_to_srgb(0.5f));
    m.alpha_mode = AlphaMode::Opaque;  // every texel counts
    EXPECT_FLOAT_EQ(material_display_color(sc, 1).r, linear_to_srgb(0.55f));
}

}  // namespace
}  // namespace aq::scene
