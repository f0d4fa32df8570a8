#include "raster/pipeline.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace penumbra::raster {

namespace {
int arenaThreads(int requested) {
  return requested > 0 ? requested : tbb::this_task_arena::max_concurrency();
}
}  // namespace

Rasterizer::Rasterizer(const RasterConfig& config) : config_(config), arena_(arenaThreads(config.threads)) {
  auto check = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("RasterConfig: ") + what);
  };
  check(config.threads >= 0 && config.threads <= 1024, "threads must be in [0, 1024]");
  check(config.tileLog2 >= kBlockLog2 && config.tileLog2 <= 10, "tileLog2 must be in [3, 10]");
  check(config.chunkTriangles >= 64 && config.chunkTriangles <= (1 << 20), "chunkTriangles must be in [64, 2^20]");
  check(config.batchChunks >= 0 && config.batchChunks <= (1 << 20), "batchChunks must be in [0, 2^20]");
  check(isSupportedSimdTarget(config.simd.tile) && isSupportedSimdTarget(config.simd.splat) &&
            isSupportedSimdTarget(config.simd.taps) && isSupportedSimdTarget(config.simd.setup) &&
            isSupportedSimdTarget(config.simd.shade),
        "simd targets must be 0 or supported by this CPU (supportedSimdTargets)");
}

void Rasterizer::checkDraw(const DrawDesc& desc, const DepthTarget& depth) const {
  if (desc.varyings < 0 || desc.varyings > kMaxVaryings)
    throw std::invalid_argument("DrawDesc: varyings must be in [0, " + std::to_string(kMaxVaryings) + "]");
  if (depth.width() < 1 || depth.height() < 1 || depth.width() > kMaxTargetSize || depth.height() > kMaxTargetSize)
    throw std::invalid_argument("depth target must be 1 to " + std::to_string(kMaxTargetSize) + " pixels a side");
}

void Rasterizer::clear(DepthTarget& depth, float value) {
  arena_.execute([&] { depth.clear(value); });
}

void Rasterizer::reproject(const Viewport& vp) {
  const GuardPlanes guard = guardPlanes(vp);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, clip_.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    projectVertices(&clip_[r.begin()].x, r.size(), vp, guard, &screen_[r.begin()], config_.simd.setup);
  });
}

void Rasterizer::runBatches(const DrawDesc& desc, DepthTarget& depth, const Viewport& vp, bool wantAttrs,
                            FragmentSink sink, void* user, PassStats& stats) {
  grid_ = tileGrid(vp.width, vp.height);
  tileStats_.assign(grid_.count(), PassStats{});
  const uint64_t triCount = desc.indices.empty() ? desc.vertexCount / 3 : desc.indices.size() / 3;
  const int batchChunks = config_.batchChunks > 0 ? config_.batchChunks : 512;
  const uint64_t batch = static_cast<uint64_t>(config_.chunkTriangles) * static_cast<uint64_t>(batchChunks);
  for (uint64_t first = 0; first < triCount; first += batch) {
    const auto t0 = Clock::now();
    frontEnd(desc, vp, wantAttrs, first, std::min(triCount, first + batch), stats);
    const auto t1 = Clock::now();
    tileStage(desc, depth, sink, user);
    stats.msSetupBin += ms(t0, t1);
    stats.msRaster += ms(t1, Clock::now());
  }
  for (PassStats& st : tileStats_) {
    st.tilesTotal = 1;
    st.tilesSkipped = 1 - st.tilesTouched;
    stats += st;
  }
}

void Rasterizer::frontEnd(const DrawDesc& desc, const Viewport& vp, bool wantAttrs, uint64_t batchFirst,
                          uint64_t batchLast, PassStats& stats) {
  const uint64_t chunkSize = static_cast<uint64_t>(config_.chunkTriangles);
  chunkCount_ = static_cast<size_t>((batchLast - batchFirst + chunkSize - 1) / chunkSize);
  if (chunks_.size() < chunkCount_) {
    chunks_.resize(chunkCount_);
    bins_.resize(chunkCount_);
  }
  const VertexStageOutput vs{clip_, screen_, vary_.data(), nv_};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, chunkCount_, 1), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t ci = r.begin(); ci != r.end(); ++ci) {
      const uint64_t first = batchFirst + ci * chunkSize, last = std::min(batchLast, first + chunkSize);
      AssembledChunk& c = chunks_[ci];
      assembleTriangles(vs, desc.indices, desc.vertexCount, desc.cull, vp, wantAttrs, first, last, c,
                        config_.simd.setup);
      binRects(
          grid_, static_cast<uint32_t>(c.tris.size()),
          [&](uint32_t i) {
            const SetupTri& t = c.tris[i];
            return PixelRect{t.minX, t.minY, t.maxX, t.maxY};
          },
          bins_[ci]);
      c.stats.binEntries = bins_[ci].entries.size();
    }
  });
  for (size_t ci = 0; ci < chunkCount_; ++ci) stats += chunks_[ci].stats;
}

void Rasterizer::tileStage(const DrawDesc& desc, DepthTarget& depth, FragmentSink sink, void* user) {
  const uint32_t numTiles = grid_.count();
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, numTiles, 1), [&](const tbb::blocked_range<uint32_t>& r) {
    TileWork& s = scratch_.local();
    for (uint32_t tIdx = r.begin(); tIdx != r.end(); ++tIdx) {
      PassStats& st = tileStats_[tIdx];
      s.tris.clear();
      s.chunkOf.clear();
      s.hits.clear();
      for (size_t ci = 0; ci < chunkCount_; ++ci) {
        const auto& tris = chunks_[ci].tris;
        for (uint32_t e : bins_[ci].tile(tIdx)) {
          s.tris.push_back(&tris[e]);
          s.chunkOf.push_back(static_cast<uint32_t>(ci));
        }
      }
      if (s.tris.empty()) continue;
      st.tilesTouched = 1;
      const PixelRect rect = grid_.rect(tIdx);
      TileJob job;
      job.x0 = rect.x0;
      job.y0 = rect.y0;
      job.x1 = rect.x1 + 1;
      job.y1 = rect.y1 + 1;
      job.width = depth.width();
      job.height = depth.height();
      job.depth = depth.image().data();
      job.depthStride = depth.image().stride();
      job.blockMin = depth.blockMin();
      job.blockMax = depth.blockMax();
      job.blocksX = depth.blocksX();
      job.func = desc.depthFunc;
      job.depthWrite = desc.depthWrite;
      job.tris = s.tris.data();
      job.count = static_cast<uint32_t>(s.tris.size());
      job.hits = sink ? &s.hits : nullptr;
      job.simd = config_.simd.tile;
      rasterizeTile(job, st);
      if (sink) sink(user, tIdx, s, *this);
    }
  });
}

}  // namespace penumbra::raster
