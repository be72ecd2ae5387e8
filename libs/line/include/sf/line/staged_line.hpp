// A larger line made from a smaller one, for the scheduling benchmark and for
// tests at scale: the base line's robot cells repeated as stages one after
// another on the loop between the uploader and the downloader.
//
//   uploader ─► U ─┬─► cell belts ──┬─► D₁ ─┬─► cell belts ──┬─► D₂ ─► … ─► Dₙ (downloader) ─► R ─► U
//                  └─► (stage 1) ───┘       └─► (stage 2) ───┘
//
// The base must have this shape with one stage: the uploader's belt U feeds
// the cell belts (robot stations only), every cell belt feeds the
// downloader's belt D, D feeds the return belt R and R feeds U. Each stage is
// a copy of the cell belts and of D (with its robots and dispensers), moved
// by D's exit minus U's exit so that it begins where the previous one ends;
// only the last D keeps the download station, and R is stretched back from
// there. One uploader and one downloader serve every stage: a layout has one
// of each. Every box still passes every stage, so a stage's belts are shared
// by all boxes (belt blocks); what grows is the number of machines a product
// can choose from and the boxes the loop can hold (its shortest cycle grows
// with the stages, and with it the order service's safe WIP).
//
// Names of stage k ≥ 2 get "-k" (belts, robots, dispensers); stage 1 keeps the base's.
#pragma once

#include "sf/core/result.hpp"
#include "sf/line/layout.hpp"

namespace sf::line {

// `stages` ≥ 1 copies of the base's cells; the result passes every layout check.
Result<Layout> staged_line(const Layout& base, int stages);

}  // namespace sf::line
