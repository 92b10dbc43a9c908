#include "deepsea/batch/contact_sheet.h"

#include <algorithm>
#include <cmath>

#include "deepsea/optics/normals.h"

namespace deepsea {

Image downscale(const Image& img, int width) {
    const int w = std::max(1, width);
    const int h = std::max(1, int(std::lround(double(img.height) * w / img.width)));
    Image out(w, h, 3);
    for (int y = 0; y < h; ++y) {
        const int y0 = y * img.height / h, y1 = std::max(y0 + 1, (y + 1) * img.height / h);
        for (int x = 0; x < w; ++x) {
            const int x0 = x * img.width / w, x1 = std::max(x0 + 1, (x + 1) * img.width / w);
            double acc[3] = {0, 0, 0};
            for (int sy = y0; sy < y1; ++sy) {
                for (int sx = x0; sx < x1; ++sx) {
                    for (int c = 0; c < 3; ++c)
                        acc[c] += img.at(sx, sy, std::min(c, img.channels - 1));
                }
            }
            const double n = double(y1 - y0) * (x1 - x0);
            for (int c = 0; c < 3; ++c) out.at(x, y, c) = float(acc[c] / n);
        }
    }
    return out;
}

Image depth_picture(const Image& depth) {
    double lo = 1e30, hi = 0.0;
    for (float z : depth.data) {
        if (has_surface(z)) {
            lo = std::min(lo, double(z));
            hi = std::max(hi, double(z));
        }
    }
    Image out(depth.width, depth.height, 3);
    const double span = hi > lo ? hi - lo : 1.0;
    for (int y = 0; y < depth.height; ++y) {
        for (int x = 0; x < depth.width; ++x) {
            const float z = depth.at(x, y);
            // near bright; the curve keeps relief visible on a mostly flat floor
            const float g =
                has_surface(z) ? float(0.05 + 0.9 * std::pow(1.0 - (z - lo) / span, 2.2)) : 0.0f;
            for (int c = 0; c < 3; ++c) out.at(x, y, c) = g;
        }
    }
    return out;
}

Image contact_sheet(const std::vector<std::vector<Image>>& rows, int tile_width) {
    constexpr int kGap = 4;
    std::vector<std::vector<Image>> tiles;
    int tile_h = 0, cols = 0;
    for (const auto& row : rows) {
        tiles.emplace_back();
        for (const Image& img : row) {
            tiles.back().push_back(downscale(img, tile_width));
            tile_h = std::max(tile_h, tiles.back().back().height);
        }
        cols = std::max(cols, int(row.size()));
    }
    const int W = cols * tile_width + (cols + 1) * kGap;
    const int H = int(rows.size()) * tile_h + (int(rows.size()) + 1) * kGap;
    Image sheet(W, H, 3, 0.01f);
    for (std::size_t r = 0; r < tiles.size(); ++r) {
        for (std::size_t c = 0; c < tiles[r].size(); ++c) {
            const Image& t = tiles[r][c];
            const int ox = kGap + int(c) * (tile_width + kGap),
                      oy = kGap + int(r) * (tile_h + kGap);
            for (int y = 0; y < t.height; ++y) {
                for (int x = 0; x < t.width; ++x) {
                    for (int ch = 0; ch < 3; ++ch) sheet.at(ox + x, oy + y, ch) = t.at(x, y, ch);
                }
            }
        }
    }
    return sheet;
}

}  // namespace deepsea
