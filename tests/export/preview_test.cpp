#include "export/preview.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/shapes.h"

namespace s2p {
namespace {

Rgb pixel(const Image& im, int x, int y) {
  const std::size_t i = (std::size_t(y) * im.width + x) * 3;
  return {im.rgb[i], im.rgb[i + 1], im.rgb[i + 2]};
}

int brightness(Rgb c) {
  return c.r + c.g + c.b;
}

bool isRed(Rgb c) {
  return c.r > 150 && c.g < 60 && c.b < 60;
}
bool isBlue(Rgb c) {
  return c.b > 150 && c.r < 60 && c.g < 60;
}

// Pixels of panel `p` satisfying `pred`.
template <class Pred>
int countIn(const Image& im, const ViewPanel& p, Pred pred) {
  int n = 0;
  for (int y = 0; y < im.height; ++y)
    for (int x = p.x0; x < p.x0 + p.width; ++x) n += pred(pixel(im, x, y)) ? 1 : 0;
  return n;
}

// Columns of panel `p` holding at least one non-background pixel: {first, last} relative to x0.
std::pair<int, int> occupiedColumns(const Image& im, const ViewPanel& p, Rgb background) {
  int first = -1, last = -1;
  for (int x = 0; x < p.width; ++x)
    for (int y = 0; y < im.height; ++y)
      if (!(pixel(im, p.x0 + x, y) == background)) {
        if (first < 0) first = x;
        last = x;
        break;
      }
  return {first, last};
}

// Axis-aligned box [-sx/2, sx/2]×[0, sy]×[-sz/2, sz/2], outward normals.
TriMesh makeBox(double sx, double sy, double sz) {
  TriMesh m;
  m.V.resize(8, 3);
  for (int i = 0; i < 8; ++i)
    m.V.row(i) << ((i & 1) ? 0.5 : -0.5) * sx, ((i & 2) ? 1.0 : 0.0) * sy,
        ((i & 4) ? 0.5 : -0.5) * sz;
  m.F.resize(12, 3);
  m.F << 0, 2, 1, 1, 2, 3,  // z-
      4, 5, 6, 5, 7, 6,     // z+
      0, 1, 4, 1, 5, 4,     // y-
      2, 6, 3, 3, 6, 7,     // y+
      0, 4, 2, 2, 4, 6,     // x-
      1, 3, 5, 3, 7, 5;     // x+
  return m;
}

TriMesh translated(TriMesh m, const Eigen::Vector3d& t) {
  m.V.rowwise() += t.transpose();
  return m;
}

TEST(Preview, ParseViewNames) {
  EXPECT_EQ(parseView("front"), View::Front);
  EXPECT_EQ(parseView("Back"), View::Back);
  EXPECT_EQ(parseView("left"), View::Left);
  EXPECT_EQ(parseView("right"), View::Right);
  EXPECT_EQ(parseView("three-quarter"), View::ThreeQuarter);
  EXPECT_EQ(parseView("side"), std::nullopt);
  EXPECT_EQ(parseView(""), std::nullopt);
  for (View v : {View::Front, View::Back, View::Left, View::Right, View::ThreeQuarter})
    EXPECT_EQ(parseView(toString(v)), v);
}

TEST(Preview, ViewRotationsFollowTheSceneConventions) {
  const Eigen::Vector3d toCamera(0, 0, 1), right(1, 0, 0), up(0, 1, 0);
  for (View v : {View::Front, View::Back, View::Left, View::Right, View::ThreeQuarter}) {
    const Eigen::Matrix3d R = viewRotation(v);
    EXPECT_NEAR((R * R.transpose() - Eigen::Matrix3d::Identity()).norm(), 0, 1e-12);
    EXPECT_NEAR(R.determinant(), 1, 1e-12);
    EXPECT_NEAR((R * Eigen::Vector3d::UnitY() - up).norm(), 0, 1e-12);  // +Y up everywhere
  }
  // Where the camera sits (world direction mapped to "towards the camera").
  const double h = std::numbers::sqrt2 / 2;
  EXPECT_NEAR((viewRotation(View::Front) * Eigen::Vector3d(0, 0, 1) - toCamera).norm(), 0, 1e-12);
  EXPECT_NEAR((viewRotation(View::Back) * Eigen::Vector3d(0, 0, -1) - toCamera).norm(), 0, 1e-12);
  EXPECT_NEAR((viewRotation(View::Left) * Eigen::Vector3d(1, 0, 0) - toCamera).norm(), 0, 1e-12);
  EXPECT_NEAR((viewRotation(View::Right) * Eigen::Vector3d(-1, 0, 0) - toCamera).norm(), 0, 1e-12);
  EXPECT_NEAR((viewRotation(View::ThreeQuarter) * Eigen::Vector3d(h, 0, h) - toCamera).norm(), 0,
              1e-12);
  // Left side view: the person's front (+Z) is on the image's left.
  EXPECT_NEAR((viewRotation(View::Left) * Eigen::Vector3d(0, 0, 1) + right).norm(), 0, 1e-12);
}

TEST(Preview, SphereRendersAsASymmetricLambertDisc) {
  const TriMesh sphere = makeIcosphere(4);
  Scene scene;
  scene.meshes.push_back({.mesh = &sphere});
  RenderOptions options{.heightPx = 512, .supersample = 3};
  std::vector<ViewPanel> panels;
  const Image im = renderScene(scene, options, &panels);
  ASSERT_EQ(panels.size(), 1u);
  const ViewPanel& p = panels[0];
  EXPECT_EQ(im.height, 512);
  EXPECT_EQ(im.width, p.width);

  // Framing: the vertices' height fills the image minus the margins.
  const BoundingBox box = boundingBox(sphere.V);
  const double marginPx = std::round(0.05 * 512);
  EXPECT_NEAR(p.pixelsPerMetre, (512 - 2 * marginPx) / box.extent().y(), 1e-9);

  // Silhouette area: π r² with r = 1 m.
  const Rgb white{255, 255, 255};
  const int covered = countIn(im, p, [&](Rgb c) { return !(c == white); });
  const double r = p.pixelsPerMetre;
  const double expected = std::numbers::pi * r * r;
  EXPECT_NEAR(covered / double(im.width * im.height), expected / (im.width * im.height),
              0.02 * expected / (im.width * im.height));

  // Lambert: the centre faces the light, the rim is grazing.
  const int cx = im.width / 2, cy = im.height / 2;
  const Rgb centre = pixel(im, cx, cy);
  const Rgb rimLeft = pixel(im, cx - static_cast<int>(0.95 * r), cy);
  const Rgb rimBottom = pixel(im, cx, cy + static_cast<int>(0.95 * r));
  EXPECT_GT(brightness(centre), brightness(rimLeft) + 150);
  EXPECT_GT(brightness(centre), brightness(rimBottom) + 150);
  EXPECT_EQ(centre.r, centre.g);  // flat grey stays grey

  // Left-right mirror symmetry.
  double sumDiff = 0;
  int bad = 0;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width / 2; ++x) {
      const int d =
          std::abs(brightness(pixel(im, x, y)) - brightness(pixel(im, im.width - 1 - x, y)));
      sumDiff += d;
      bad += d > 24 ? 1 : 0;
    }
  EXPECT_LT(sumDiff / (im.width / 2 * im.height), 1.0);
  EXPECT_LT(bad, 0.002 * im.width * im.height);
}

TEST(Preview, ViewConventionsPutTheColouredHalvesOnTheRightSide) {
  // Person's right (−X) red, person's left (+X) blue.
  const TriMesh sphere = makeIcosphere(3);
  Eigen::MatrixX3d colour(sphere.numVertices(), 3);
  for (int v = 0; v < sphere.numVertices(); ++v)
    colour.row(v) = sphere.V(v, 0) <= 0 ? Eigen::RowVector3d(1, 0, 0) : Eigen::RowVector3d(0, 0, 1);
  Scene scene;
  scene.meshes.push_back({.mesh = &sphere, .colour = &colour});
  RenderOptions options{.views = {View::Front, View::Back, View::Left, View::Right},
                        .heightPx = 200};
  std::vector<ViewPanel> panels;
  const Image im = renderScene(scene, options, &panels);
  ASSERT_EQ(panels.size(), 4u);
  const int cy = im.height / 2;
  const int q = static_cast<int>(0.5 * panels[0].pixelsPerMetre);  // half a radius
  auto at = [&](int view, int dx) {
    return pixel(im, panels[view].x0 + panels[view].width / 2 + dx, cy);
  };
  // Front: camera on +Z, +X on the image's right → red (−X) on the left.
  EXPECT_TRUE(isRed(at(0, -q)));
  EXPECT_TRUE(isBlue(at(0, q)));
  // Back: mirrored.
  EXPECT_TRUE(isBlue(at(1, -q)));
  EXPECT_TRUE(isRed(at(1, q)));
  // Left side sees only the +X half, right side only the −X half.
  EXPECT_TRUE(isBlue(at(2, 0)));
  EXPECT_TRUE(isBlue(at(2, -q)) && isBlue(at(2, q)));
  EXPECT_TRUE(isRed(at(3, 0)));
  EXPECT_TRUE(isRed(at(3, -q)) && isRed(at(3, q)));
}

TEST(Preview, SideViewsShowTheFrontOnTheExpectedSide) {
  // Front (+Z) half red, back half blue: facing left in the left view, right in the right view.
  const TriMesh sphere = makeIcosphere(3);
  Eigen::MatrixX3d colour(sphere.numVertices(), 3);
  for (int v = 0; v < sphere.numVertices(); ++v)
    colour.row(v) = sphere.V(v, 2) >= 0 ? Eigen::RowVector3d(1, 0, 0) : Eigen::RowVector3d(0, 0, 1);
  Scene scene;
  scene.meshes.push_back({.mesh = &sphere, .colour = &colour});
  std::vector<ViewPanel> panels;
  const Image im =
      renderScene(scene, {.views = {View::Left, View::Right}, .heightPx = 200}, &panels);
  const int q = static_cast<int>(0.5 * panels[0].pixelsPerMetre);
  auto at = [&](int view, int dx) {
    return pixel(im, panels[view].x0 + panels[view].width / 2 + dx, im.height / 2);
  };
  EXPECT_TRUE(isRed(at(0, -q)));
  EXPECT_TRUE(isBlue(at(0, q)));
  EXPECT_TRUE(isBlue(at(1, -q)));
  EXPECT_TRUE(isRed(at(1, q)));
}

TEST(Preview, CurveOnTheEquatorIsHiddenWhereItPassesBehind) {
  const TriMesh sphere = makeIcosphere(4);
  auto arc = [](double t0, double t1) {
    const int n = 64;
    Eigen::MatrixX3d P(n, 3);
    for (int i = 0; i < n; ++i) {
      const double t = t0 + (t1 - t0) * i / (n - 1);
      P.row(i) << std::cos(t), 0, std::sin(t);  // on the unit sphere's equator
    }
    return P;
  };
  const double pi = std::numbers::pi;
  Scene scene;
  scene.meshes.push_back({.mesh = &sphere});
  scene.lines.push_back({.points = arc(0.2, pi - 0.2), .colour = {255, 0, 0}});           // z > 0
  scene.lines.push_back({.points = arc(pi + 0.2, 2 * pi - 0.2), .colour = {0, 0, 255}});  // z < 0
  std::vector<ViewPanel> panels;
  const Image im =
      renderScene(scene, {.views = {View::Front, View::Back}, .heightPx = 256}, &panels);
  const int arcPixels = static_cast<int>(1.6 * panels[0].pixelsPerMetre);  // ≥ 0.8 of 2 r × 1 px
  EXPECT_GT(countIn(im, panels[0], isRed), arcPixels);
  EXPECT_EQ(countIn(im, panels[0], isBlue), 0);
  EXPECT_GT(countIn(im, panels[1], isBlue), arcPixels);
  EXPECT_EQ(countIn(im, panels[1], isRed), 0);

  // A curve 1 cm inside the surface (mesh noise, cut vertices) is still drawn: depth bias.
  Scene sunk;
  sunk.meshes.push_back({.mesh = &sphere});
  sunk.lines.push_back({.points = 0.99 * arc(0.2, pi - 0.2), .colour = {255, 0, 0}});
  const Image sunkIm = renderScene(sunk, {.heightPx = 256}, &panels);
  EXPECT_GT(countIn(sunkIm, panels[0], isRed), arcPixels);

  // Always-on-top curves show through.
  scene.lines[1].onTop = true;
  const Image top = renderScene(scene, {.views = {View::Front}, .heightPx = 256}, &panels);
  EXPECT_GT(countIn(top, panels[0], isBlue), arcPixels);
}

TEST(Preview, PointsAreDiscsHiddenBehindTheSurface) {
  const TriMesh sphere = makeIcosphere(4);
  Scene scene;
  scene.meshes.push_back({.mesh = &sphere});
  Eigen::MatrixX3d P(1, 3);
  P << 0, 0, 1;  // on the front of the sphere
  scene.points.push_back({.points = P, .colour = {255, 0, 0}, .radiusPx = 6});
  std::vector<ViewPanel> panels;
  const Image im = renderScene(
      scene, {.views = {View::Front, View::Back}, .heightPx = 200, .supersample = 3}, &panels);
  const double disc = std::numbers::pi * 6 * 6;
  EXPECT_NEAR(countIn(im, panels[0], isRed), disc, 0.25 * disc);
  EXPECT_EQ(countIn(im, panels[1], isRed), 0);
}

TEST(Preview, SmallSphereBehindABigOneIsOccluded) {
  const TriMesh big = makeIcosphere(4, 1.0);
  const TriMesh small = translated(makeIcosphere(3, 0.3), Eigen::Vector3d(0, 0, -2));
  Scene scene;
  scene.meshes.push_back({.mesh = &big});
  scene.meshes.push_back({.mesh = &small, .flatColour = {255, 0, 0}});
  auto reddish = [](Rgb c) { return c.r > c.g + 40; };
  std::vector<ViewPanel> panels;
  const Image im =
      renderScene(scene, {.views = {View::Front, View::Back}, .heightPx = 256}, &panels);
  EXPECT_EQ(countIn(im, panels[0], reddish), 0);
  const double r = 0.3 * panels[1].pixelsPerMetre;
  EXPECT_NEAR(countIn(im, panels[1], reddish), std::numbers::pi * r * r,
              0.1 * std::numbers::pi * r * r);
}

TEST(Preview, ThreeQuarterWidthLiesBetweenFrontAndSide) {
  const double a = 1.0, height = 2.0, b = 0.2;
  const TriMesh box = makeBox(a, height, b);
  Scene scene;
  scene.meshes.push_back({.mesh = &box, .smooth = false});
  const Rgb white{255, 255, 255};
  std::vector<ViewPanel> panels;
  const Image im = renderScene(
      scene, {.views = {View::Front, View::Left, View::ThreeQuarter}, .heightPx = 300}, &panels);
  ASSERT_EQ(panels.size(), 3u);
  double width[3];
  for (int v = 0; v < 3; ++v) {
    const auto [first, last] = occupiedColumns(im, panels[v], white);
    ASSERT_GE(first, 0);
    width[v] = last - first + 1;
  }
  const double ppm = panels[0].pixelsPerMetre;
  EXPECT_NEAR(width[0], a * ppm, 2.0);
  EXPECT_NEAR(width[1], b * ppm, 2.0);
  EXPECT_NEAR(width[2], (a + b) / std::numbers::sqrt2 * ppm, 2.0);
  EXPECT_GT(width[2], width[1] + 10);
  EXPECT_LT(width[2], width[0] - 10);
}

TEST(Preview, ViewsShareOneScaleAndAreLaidOutWithGaps) {
  const TriMesh box = makeBox(1.0, 2.0, 0.4);
  Scene scene;
  scene.meshes.push_back({.mesh = &box});
  RenderOptions options{.views = {View::Front, View::Left, View::Back},
                        .heightPx = 128,
                        .background = {0, 64, 0},
                        .gapPx = 10};
  std::vector<ViewPanel> panels;
  const Image im = renderScene(scene, options, &panels);
  const int margin = static_cast<int>(std::lround(0.05 * 128));
  const double ppm = (128 - 2.0 * margin) / 2.0;
  ASSERT_EQ(panels.size(), 3u);
  for (const ViewPanel& p : panels) EXPECT_DOUBLE_EQ(p.pixelsPerMetre, ppm);
  EXPECT_EQ(panels[0].width, static_cast<int>(std::ceil(1.0 * ppm)) + 2 * margin);
  EXPECT_EQ(panels[1].width, static_cast<int>(std::ceil(0.4 * ppm)) + 2 * margin);
  EXPECT_EQ(panels[1].x0, panels[0].width + 10);
  EXPECT_EQ(panels[2].x0, panels[1].x0 + panels[1].width + 10);
  EXPECT_EQ(im.width, panels[2].x0 + panels[2].width);
  for (int x = panels[0].width; x < panels[1].x0; ++x)
    for (int y = 0; y < im.height; ++y) ASSERT_EQ(pixel(im, x, y), (Rgb{0, 64, 0}));
}

TEST(Preview, SemiTransparentMeshBlendsOverTheOpaqueOne) {
  const TriMesh inner = makeIcosphere(4, 0.5);
  const TriMesh outer = makeIcosphere(4, 1.0);
  const RenderOptions options{.heightPx = 128};
  auto centreOf = [&](const Scene& s) {
    const Image im = renderScene(s, options);
    return pixel(im, im.width / 2, im.height / 2);
  };
  Scene red, blue, both;
  red.meshes.push_back({.mesh = &inner, .flatColour = {255, 0, 0}});
  blue.meshes.push_back({.mesh = &outer, .flatColour = {0, 0, 255}});
  both.meshes.push_back({.mesh = &outer, .flatColour = {0, 0, 255}, .opacity = 0.25f});
  both.meshes.push_back({.mesh = &inner, .flatColour = {255, 0, 0}});
  const Rgb r = centreOf(red), b = centreOf(blue), mix = centreOf(both);
  // Both centres face the camera: same shading, so the blend is 0.75 red + 0.25 blue.
  EXPECT_NEAR(mix.r, 0.75 * r.r + 0.25 * b.r, 1.5);
  EXPECT_NEAR(mix.b, 0.75 * r.b + 0.25 * b.b, 1.5);
  EXPECT_GT(mix.b, 40);
}

TEST(Preview, CaptionsAreDrawnCentredInTheTopMargin) {
  const TriMesh sphere = makeIcosphere(2);
  Scene scene;
  scene.meshes.push_back({.mesh = &sphere});
  // Height 400: 20 px margin, font scale 2; a dash is 5×1 font pixels.
  std::vector<ViewPanel> panels;
  const Image im = renderScene(
      scene, {.views = {View::Front, View::Back}, .heightPx = 400, .captions = {"-", ""}}, &panels);
  const Image plain = renderScene(scene, {.views = {View::Front, View::Back}, .heightPx = 400});
  int changed = 0, minX = im.width, maxX = -1;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x)
      if (!(pixel(im, x, y) == pixel(plain, x, y))) {
        ++changed;
        EXPECT_EQ(pixel(im, x, y), (Rgb{40, 40, 40}));
        EXPECT_LT(y, 20);
        minX = std::min(minX, x);
        maxX = std::max(maxX, x);
      }
  EXPECT_EQ(changed, 5 * 2 * 2);
  EXPECT_EQ(minX + maxX + 1, panels[0].width - (panels[0].width - 10) % 2);  // centred
  EXPECT_THROW(renderScene(scene, {.heightPx = 400, .captions = {"a", "b"}}), InputError);
}

TEST(Preview, CurvesOnATransparentSurfaceStaySharpAndCurvesBehindItAreTinted) {
  const TriMesh sphere = makeIcosphere(4);
  auto arc = [](double t0, double t1) {
    Eigen::MatrixX3d P(33, 3);
    for (int i = 0; i < 33; ++i) {
      const double t = t0 + (t1 - t0) * i / 32;
      P.row(i) << std::cos(t), 0, std::sin(t);
    }
    return P;
  };
  const double pi = std::numbers::pi;
  const Rgb green{0, 200, 0};
  auto centreOf = [&](const Eigen::MatrixX3d& curve, float opacity) {
    Scene s;
    s.meshes.push_back({.mesh = &sphere, .flatColour = {0, 0, 255}, .opacity = opacity});
    s.lines.push_back({.points = curve, .colour = green, .widthPx = 6});
    const Image im = renderScene(s, {.heightPx = 128});
    return pixel(im, im.width / 2, im.height / 2);
  };
  // On the near surface: the curve is drawn as is.
  EXPECT_EQ(centreOf(arc(0.3, pi - 0.3), 0.5f), green);
  // Behind the near surface (on the far side): seen through it, blended half and half.
  const Rgb surface = centreOf(Eigen::MatrixX3d(0, 3), 1.0f);
  const Rgb through = centreOf(arc(pi + 0.3, 2 * pi - 0.3), 0.5f);
  EXPECT_NEAR(through.g, 0.5 * green.g + 0.5 * surface.g, 1.5);
  EXPECT_NEAR(through.b, 0.5 * green.b + 0.5 * surface.b, 1.5);
}

TEST(Preview, RenderingIsDeterministic) {
  const TriMesh sphere = makeIcosphere(4);
  Scene scene;
  scene.meshes.push_back({.mesh = &sphere, .opacity = 0.5f});
  const RenderOptions options{.views = {View::ThreeQuarter, View::Back}, .heightPx = 200};
  EXPECT_EQ(renderScene(scene, options).rgb, renderScene(scene, options).rgb);
}

TEST(Preview, EmptySceneGivesBackgroundPanels) {
  const Image im = renderScene(
      Scene{},
      {.views = {View::Front, View::Back}, .heightPx = 64, .background = {1, 2, 3}, .gapPx = 4});
  EXPECT_EQ(im.height, 64);
  EXPECT_EQ(im.width, 64 + 4 + 64);
  for (int i = 0; i < im.width * im.height; ++i)
    ASSERT_EQ(pixel(im, i % im.width, i / im.width), (Rgb{1, 2, 3}));
}

TEST(Preview, BadInputThrowsInputError) {
  const TriMesh sphere = makeIcosphere(1);
  Scene ok;
  ok.meshes.push_back({.mesh = &sphere});
  EXPECT_THROW(renderScene(ok, {.views = {}}), InputError);
  EXPECT_THROW(renderScene(ok, {.heightPx = 0}), InputError);
  EXPECT_THROW(renderScene(ok, {.heightPx = 100000}), InputError);
  EXPECT_THROW(renderScene(ok, {.supersample = 0}), InputError);
  EXPECT_THROW(renderScene(ok, {.margin = std::nan("")}), InputError);
  Scene nullMesh;
  nullMesh.meshes.push_back({.mesh = nullptr});
  EXPECT_THROW(renderScene(nullMesh, {}), InputError);
  const Eigen::MatrixX3d wrongRows = Eigen::MatrixX3d::Zero(3, 3);
  Scene wrongColour;
  wrongColour.meshes.push_back({.mesh = &sphere, .colour = &wrongRows});
  EXPECT_THROW(renderScene(wrongColour, {}), InputError);
  TriMesh badIndex = sphere;
  badIndex.F(0, 0) = 1000;
  Scene badMesh;
  badMesh.meshes.push_back({.mesh = &badIndex});
  EXPECT_THROW(renderScene(badMesh, {}), InputError);
  Scene nanLine = ok;
  nanLine.lines.push_back({.points = Eigen::MatrixX3d::Constant(2, 3, std::nan(""))});
  EXPECT_THROW(renderScene(nanLine, {}), InputError);
  Scene zeroWidth = ok;
  zeroWidth.lines.push_back({.points = Eigen::MatrixX3d::Zero(2, 3), .widthPx = 0});
  EXPECT_THROW(renderScene(zeroWidth, {}), InputError);
  Scene far = ok;
  far.points.push_back({.points = Eigen::MatrixX3d::Constant(1, 3, 1e300)});
  EXPECT_THROW(renderScene(far, {}), InputError);
  Scene badOpacity = ok;
  badOpacity.meshes[0].opacity = 2.0f;
  EXPECT_THROW(renderScene(badOpacity, {}), InputError);
}

}  // namespace
}  // namespace s2p
