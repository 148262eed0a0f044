// SPDX-License-Identifier: GPL-3.0-or-later
// canonform: the SIFT extractor's scale space (private to the views area): images over their
// supports, the Gaussian blur, an octave's Gaussian images and the rows of its difference-of-
// Gaussian images. Step 1 of sift_features.h (Lowe Sec. 3, eq. 1) says what they compute.
#pragma once

#include <algorithm>
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

namespace canonform::views {
namespace sift {

// A half-open rectangle of pixels [x0, x1) x [y0, y1) in an octave's integer coordinates (pixel X
// of octave o is view position X 2^o).
struct Rect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x1 <= x0 || y1 <= y0; }
    Rect grown(int m) const { return {x0 - m, y0 - m, x1 + m, y1 + m}; }
    Rect meet(const Rect& o) const {
        return {std::max(x0, o.x0), std::max(y0, o.y0), std::min(x1, o.x1), std::min(y1, o.y1)};
    }
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
};

// One image of an octave: values over `support`, 0 outside it (never read there); stored in a
// buffer covering `frame` (row y, column x at data[(y - frame.y0) * stride + x - frame.x0]).
struct Plane {
    float* data = nullptr;
    Rect frame, support;
    int stride = 0;
    float* row(int y) const { return data + static_cast<std::ptrdiff_t>(y - frame.y0) * stride - frame.x0; }
    float at(int x, int y) const { return row(y)[x]; }
};

// A symmetric Gaussian kernel truncated at 3 sigma: taps[0..radius], normalised so that the
// whole kernel sums to 1 (in double, then rounded to float).
struct Kernel {
    int radius = 0;
    std::vector<float> taps;
};

// The kernel's radius, ceil(3 sigma) (at least 1): also how far an image's support reaches beyond
// the object's box.
int support_radius(double sigma);
Kernel gaussian_kernel(double sigma);

// Scratch memory of an extraction, kept per thread from one view to the next (a view's planes are a
// few hundred kilobytes each).
struct Workspace {
    std::vector<float> line;
    std::vector<const float*> rows;  // the blur's rows for its vertical pass
    // Planes in two banks (octave o uses bank o % 2, so octave o - 1's planes stay readable).
    std::vector<std::unique_ptr<float[]>> planes[2];
    std::vector<size_t> plane_sizes[2];
    float* plane(int bank, int slot, size_t n);
    std::unique_ptr<float[]> temp;
    size_t temp_size = 0;
    float* temp_for(size_t n);
    std::vector<float> shifted;     // the view on the doubled image's grid (the extractor's octave 0 input)
    std::vector<float> shift_rows;  // a view row and two interpolated rows, for `shifted`
    // gaussian_kernel(sigma), made once per sigma: every octave of every view blurs with the same
    // few (a linear search by the exact value; a handful of entries).
    std::vector<std::pair<double, Kernel>> kernels;
    const Kernel& kernel(double sigma);
};

// This thread's workspace.
Workspace& workspace();

// out over out.support = in blurred by the kernel (in is 0 outside in.support); out.support must
// lie within in.support grown by the kernel's radius (the rest of the blurred image is dropped, see
// sift_features.h). Rows then columns; each output sums k0 v0 + k1 (v-1 + v+1) + ... in that order,
// so the value of a pixel does not depend on where the rectangles lie.
void blur(const Plane& in, Plane& out, const Kernel& k, Workspace& ws);

// The sampling of a scale space: s DoG layers searched per octave, the first image's blur sigma_0,
// k = 2^(1/s), the contrast threshold t on |D| and Lowe's edge ratio r.
struct Settings {
    int layers = 3;
    double sigma0 = 1.6, k = 1, threshold = 0, edge_ratio = 10;
};

// sigma_0 k^j, the blur of an octave's Gaussian image j (in octave pixels).
double layer_sigma(const Settings& st, int j);

// Octave o's Gaussian images j = 0..layers+2 into g (planes of bank o % 2 of ws), over the object's
// box `obj` (octave pixels) grown by each image's support radius. Octave 0 blurs `source` (0 outside
// its support, blur input_blur) to sigma_0; a later octave takes every second pixel of every second
// row of `source`, the previous octave's image j = layers (2 sigma_0). Each later image is the
// previous one blurred by sqrt(sigma_j^2 - sigma_(j-1)^2). The last image (j = layers + 2) is
// computed only over image layers - 1's support, where it is read.
void gaussian_octave(int o, const Rect& obj, const Plane& source, double input_blur, const Settings& st,
                     Workspace& ws, std::vector<Plane>& g);

// A DoG row d = t - b over [0, w), and the largest and the smallest of every three neighbours along
// it, mx[i] and mn[i] for i in [1, w - 1). With AVX-512 16 lanes a step, else dog_row_portable.
void dog_row(const float* b, const float* t, float* d, float* mx, float* mn, int w);
void dog_row_portable(const float* b, const float* t, float* d, float* mx, float* mn, int w);

// The positions i in [1, w - 1), ascending, where the DoG row d has a candidate: |d[i]| >= pre,
// d[i] != 0, and d[i] above (below) its 8 neighbours in the layer (the row's neighbours, and the
// rows above and below by their three-neighbour maxima and minima). Returns their number. `out`
// holds w + 16 ints (a step may write 16 past its candidates).
int row_candidates(const float* d, const float* upmax, const float* upmin, const float* downmax,
                   const float* downmin, int w, float pre, int* out);
// row_candidates without AVX-512 (the same candidates: tests compare them).
int row_candidates_portable(const float* d, const float* upmax, const float* upmin, const float* downmax,
                            const float* downmin, int w, float pre, int* out);

}  // namespace sift
}  // namespace canonform::views
