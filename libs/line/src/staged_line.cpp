#include "sf/line/staged_line.hpp"

#include <algorithm>
#include <set>

#include <fmt/format.h>

#include "layout_check.hpp"

namespace sf::line {

namespace {

std::string belt_of(std::string_view station) {
  return std::string(station.substr(0, station.find('/')));
}

// The base's loop: uploader's belt, cell belts, downloader's belt, return belt (by index).
struct Shape {
  std::size_t uploader = 0;
  std::vector<std::size_t> cells;
  std::size_t downloader = 0;
  std::size_t back = 0;
};

Error not_staged(const Layout& base, std::string_view why) {
  return Error{Errc::invalid_argument,
               fmt::format("layout '{}' cannot be repeated in stages: {}", base.line, why)};
}

Result<Shape> shape_of(const Layout& base) {
  Shape s;
  const auto u = base.belt_index(belt_of(base.uploader.station));
  const auto d = base.belt_index(belt_of(base.downloader.station));
  if (!u || !d || *u == *d) {
    return not_staged(base, "the uploader and the downloader need belts of their own");
  }
  s.uploader = *u;
  s.downloader = *d;
  const BeltSpec& down = base.belts[*d];
  if (down.next.size() != 1) {
    return not_staged(base, "the downloader's belt must feed one return belt");
  }
  s.back = *base.belt_index(down.next.front());
  const BeltSpec& back = base.belts[s.back];
  if (back.next != std::vector<std::string>{base.belts[*u].name} || !back.stations.empty() || s.back == *u) {
    return not_staged(base, "the return belt must feed the uploader's belt and have no stations");
  }
  for (const auto& name : base.belts[*u].next) {
    const std::size_t c = *base.belt_index(name);
    if (base.belts[c].next != std::vector<std::string>{down.name} || c == s.back) {
      return not_staged(base, fmt::format("cell belt '{}' must feed the downloader's belt only", name));
    }
    s.cells.push_back(c);
  }
  if (s.cells.empty()) {
    return not_staged(base, "the uploader's belt feeds no cell belts");
  }
  return s;
}

std::string staged(const std::string& name, int stage) {
  return stage == 1 ? name : fmt::format("{}-{}", name, stage);
}

Vec3 moved(Vec3 p, Vec2 by) {
  return {p.x + by.x, p.y + by.y, p.z};
}

// The belts of one stage, its robots and their dispensers, `by` further along the floor.
class StageCopier {
 public:
  StageCopier(const Layout& base, const Shape& shape, int stages)
      : base_(base),
        shape_(shape),
        stages_(stages),
        step_(base.belts[shape.downloader].path.back() - base.belts[shape.uploader].path.back()) {
    for (std::size_t c : shape.cells) {
      stage_belts_.insert(base.belts[c].name);
    }
    stage_belts_.insert(base.belts[shape.downloader].name);
  }

  void copy(int stage, Layout& out) const {
    const Vec2 by = static_cast<double>(stage - 1) * step_;
    for (std::size_t c : shape_.cells) {
      out.belts.push_back(
          belt(base_.belts[c], stage, by, {staged(base_.belts[shape_.downloader].name, stage)}));
    }
    out.belts.push_back(downloader_belt(stage, by));
    for (const RobotSpec& r : base_.robots) {
      if (!r.stations.empty() && stage_belts_.contains(belt_of(r.stations.front()))) {
        out.robots.push_back(robot(r, stage, by, out));
      }
    }
  }

  [[nodiscard]] bool in_stage(const RobotSpec& r) const {
    return !r.stations.empty() && stage_belts_.contains(belt_of(r.stations.front()));
  }
  [[nodiscard]] Vec2 end() const { return static_cast<double>(stages_ - 1) * step_; }

 private:
  BeltSpec belt(const BeltSpec& b, int stage, Vec2 by, std::vector<std::string> next) const {
    BeltSpec out = b;
    out.name = staged(b.name, stage);
    out.label = stage == 1 ? b.label : fmt::format("{} (stage {})", b.label, stage);
    out.plc.port = 0;
    for (auto& p : out.path) {
      p = p + by;
    }
    out.next = std::move(next);
    return out;
  }

  BeltSpec downloader_belt(int stage, Vec2 by) const {
    const BeltSpec& d = base_.belts[shape_.downloader];
    std::vector<std::string> next;
    if (stage == stages_) {
      next = d.next;
    } else {
      for (std::size_t c : shape_.cells) {
        next.push_back(staged(base_.belts[c].name, stage + 1));
      }
    }
    BeltSpec out = belt(d, stage, by, std::move(next));
    if (stage != stages_) {  // only the last stage's keeps the download station
      const std::string download = base_.downloader.station.substr(base_.downloader.station.find('/') + 1);
      std::erase_if(out.stations, [&](const StationSpec& s) { return s.name == download; });
    }
    return out;
  }

  RobotSpec robot(const RobotSpec& r, int stage, Vec2 by, Layout& out) const {
    RobotSpec copy = r;
    copy.name = staged(r.name, stage);
    copy.label = stage == 1 ? r.label : fmt::format("{} (stage {})", r.label, stage);
    copy.controller.port = 0;
    copy.scara.base = moved(r.scara.base, by);
    copy.articulated.base = moved(r.articulated.base, by);
    if (r.home) {
      copy.home = moved(*r.home, by);
    }
    for (auto& s : copy.stations) {
      s = staged(belt_of(s), stage) + s.substr(s.find('/'));
    }
    for (auto& name : copy.dispensers) {
      DispenserSpec d = *base_.dispenser(name);
      d.name = staged(d.name, stage);
      d.at = moved(d.at, by);
      name = d.name;
      out.dispensers.push_back(std::move(d));
    }
    return copy;
  }

  const Layout& base_;
  const Shape& shape_;
  int stages_;
  Vec2 step_;
  std::set<std::string> stage_belts_;
};

// The return belt from the last stage's end back to the uploader's belt: the first half of its
// path moves with the end of the line.
BeltSpec stretched_back(const BeltSpec& back, Vec2 by) {
  BeltSpec out = back;
  const Vec2 from = back.path.front();
  const Vec2 to = back.path.back();
  for (auto& p : out.path) {
    if (motion::norm(p - from) < motion::norm(p - to)) {
      p = p + by;
    }
  }
  return out;
}

}  // namespace

Result<Layout> staged_line(const Layout& base, int stages) {
  if (stages < 1) {
    return make_error(Errc::invalid_argument, fmt::format("{} stages: at least one", stages));
  }
  auto shape = shape_of(base);
  if (!shape) {
    return shape.error();
  }
  const StageCopier copier(base, *shape, stages);
  Layout out = base;
  out.line = stages == 1 ? base.line : fmt::format("{}-x{}", base.line, stages);
  out.belts = {base.belts[shape->uploader]};
  out.robots.clear();
  out.dispensers.clear();
  for (const RobotSpec& r : base.robots) {  // robots outside the cells stay as they are
    if (!copier.in_stage(r)) {
      out.robots.push_back(r);
      for (const auto& d : r.dispensers) {
        out.dispensers.push_back(*base.dispenser(d));
      }
    }
  }
  for (int k = 1; k <= stages; ++k) {
    copier.copy(k, out);
  }
  out.belts.push_back(stretched_back(base.belts[shape->back], copier.end()));
  for (std::size_t b = 0; b < base.belts.size(); ++b) {  // belts off the loop stay as they are
    if (b != shape->uploader && b != shape->downloader && b != shape->back &&
        std::find(shape->cells.begin(), shape->cells.end(), b) == shape->cells.end()) {
      out.belts.push_back(base.belts[b]);
    }
  }
  out.downloader.station = staged(belt_of(base.downloader.station), stages) +
                           base.downloader.station.substr(base.downloader.station.find('/'));
  SF_TRY(check_layout(out));
  return out;
}

}  // namespace sf::line
