#include "deepsea/runtime/layers.h"

namespace deepsea {

void Layers::resize(int width, int height, LayerSet set) {
    auto fit = [&](Image& img, int channels) {
        if (img.width != width || img.height != height || img.channels != channels) {
            img = Image(width, height, channels);
        }
    };
    if (set == LayerSet::Final) {
        fit(final, 3);
        for (Image* img : {&direct, &forward, &backscatter, &transmission, &depth, &normal, &mask,
                           &snow, &snow_id}) {
            *img = Image();
        }
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

const std::vector<std::string>& layer_names() {
    static const std::vector<std::string> names{"final",       "direct",       "forward",
                                                "backscatter", "transmission", "depth",
                                                "normal",      "snow",         "snow_id"};
    return names;
}

}  // namespace deepsea
