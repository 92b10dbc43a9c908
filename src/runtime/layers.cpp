#include "deepsea/runtime/layers.h"

#include "deepsea/io/image_io.h"

namespace deepsea {

void Layers::resize(int width, int height, LayerSet set) {
    auto fit = [&](Image& img, int channels) {
        if (img.width != width || img.height != height || img.channels != channels) {
            img = Image(width, height, channels);
        }
    };
    if (set == LayerSet::Final) {
        fit(final, 3);
        fit(direct, 3);
        for (Image* img : {&forward, &backscatter, &transmission, &depth, &normal}) *img = Image();
        return;
    }
    fit(final, 3);
    fit(direct, 3);
    fit(forward, 3);
    fit(backscatter, 3);
    fit(transmission, 3);
    fit(depth, 1);
    fit(normal, 3);
}

void write_layers(const std::string& path, const Layers& l, const ImageMetadata& meta) {
    const std::vector<std::string> rgb{"R", "G", "B"};
    write_exr_layers(path,
                     {{"final", &l.final, rgb},
                      {"direct", &l.direct, rgb},
                      {"forward", &l.forward, rgb},
                      {"backscatter", &l.backscatter, rgb},
                      {"transmission", &l.transmission, rgb},
                      {"depth", &l.depth, {"Z"}},
                      {"normal", &l.normal, {"X", "Y", "Z"}}},
                     meta);
}

}  // namespace deepsea
