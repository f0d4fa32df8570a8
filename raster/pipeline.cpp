#include "raster/pipeline.h"

#include <algorithm>
#include <cstring>
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

void Rasterizer::runBatches(const DrawDesc& desc, DepthTarget& depth, bool wantAttrs, FragmentSink sink, void* user,
                            PassStats& stats) {
  const Viewport vp{depth.width(), depth.height()};
  const int tileLog2 = config_.tileLog2;
  tilesX_ = (vp.width + (1 << tileLog2) - 1) >> tileLog2;
  tilesY_ = (vp.height + (1 << tileLog2) - 1) >> tileLog2;
  tileStats_.assign(static_cast<size_t>(tilesX_ * tilesY_), PassStats{});
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
  const int tileLog2 = config_.tileLog2;
  const uint32_t numTiles = static_cast<uint32_t>(tilesX_ * tilesY_);
  const bool indexed = !desc.indices.empty();
  const uint64_t chunkSize = static_cast<uint64_t>(config_.chunkTriangles);
  chunkCount_ = static_cast<size_t>((batchLast - batchFirst + chunkSize - 1) / chunkSize);
  if (chunks_.size() < chunkCount_) chunks_.resize(chunkCount_);
  const int nv = nv_;
  const uint32_t vertexCount = desc.vertexCount;
  const GuardPlanes guard = guardPlanes(vp);

  tbb::parallel_for(tbb::blocked_range<size_t>(0, chunkCount_, 1), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t ci = r.begin(); ci != r.end(); ++ci) {
      detail::Chunk& c = chunks_[ci];
      c.tris.clear();
      c.attrs.clear();
      c.clipVary.clear();
      c.stats = PassStats{};
      PassStats& st = c.stats;
      const uint64_t first = batchFirst + ci * chunkSize, last = std::min(batchLast, first + chunkSize);
      st.trianglesIn = last - first;

      auto emit = [&](const ScreenVert& a, const ScreenVert& b, const ScreenVert& d, uint32_t prim,
                      const uint32_t vref[3], bool clipped) {
        SetupTri t;
        SetupAttr at;
        int order[3];
        const SetupResult res = setupTriangle(a, b, d, desc.cull, vp, t, wantAttrs ? &at : nullptr, order);
        switch (res) {
          case SetupResult::CulledFacing: ++st.trianglesCulledFacing; return;
          case SetupResult::Degenerate: ++st.trianglesCulledDegenerate; return;
          case SetupResult::NoSample: ++st.trianglesCulledNoSample; return;
          case SetupResult::Ok: break;
        }
        t.primitive = prim;
        if (wantAttrs) {
          for (int k = 0; k < 3; ++k) {
            at.vary[k] = vref[order[k]];
            at.order[k] = static_cast<uint8_t>(order[k]);
          }
          at.clipped = clipped;
          c.attrs.push_back(at);
        }
        c.tris.push_back(t);
      };

      double clipIn[3][kClipStride];
      double poly[kMaxClipVerts * kClipStride];
      for (uint64_t tri = first; tri < last; ++tri) {
        uint32_t idx[3];
        if (indexed) {
          for (int k = 0; k < 3; ++k) idx[k] = desc.indices[tri * 3 + static_cast<uint64_t>(k)];
          if (idx[0] >= vertexCount || idx[1] >= vertexCount || idx[2] >= vertexCount) {
            ++st.trianglesDroppedInvalid;
            continue;
          }
        } else {
          for (int k = 0; k < 3; ++k) idx[k] = static_cast<uint32_t>(tri * 3 + static_cast<uint64_t>(k));
        }
        const ScreenVert& a = screen_[idx[0]];
        const ScreenVert& b = screen_[idx[1]];
        const ScreenVert& d = screen_[idx[2]];
        const uint32_t orFlags = a.flags | b.flags | d.flags;
        if (orFlags & kNonFinite) {
          ++st.trianglesDroppedInvalid;
          continue;
        }
        if (a.flags & b.flags & d.flags & kFrustumMask) {
          ++st.trianglesCulledFrustum;
          continue;
        }
        const uint32_t prim = static_cast<uint32_t>(tri);
        if (!(orFlags & kNeedsClip)) {
          emit(a, b, d, prim, idx, false);
          continue;
        }
        // Homogeneous clipping, in double. Vertex layout: position, varyings, submitted barycentrics.
        ++st.trianglesClipped;
        const int stride = 4 + nv + 3;
        const double* in[3];
        for (int k = 0; k < 3; ++k) {
          const glm::vec4& p = clip_[idx[k]];
          clipIn[k][0] = p.x;
          clipIn[k][1] = p.y;
          clipIn[k][2] = p.z;
          clipIn[k][3] = p.w;
          const float* v = vary_.data() + static_cast<size_t>(idx[k]) * static_cast<size_t>(nv);
          for (int c2 = 0; c2 < nv; ++c2) clipIn[k][4 + c2] = v[c2];
          for (int e = 0; e < 3; ++e) clipIn[k][4 + nv + e] = (e == k) ? 1.0 : 0.0;
          in[k] = clipIn[k];
        }
        const int n = clipTriangle(in, nv + 3, guard, poly);
        if (n < 3) {
          ++st.trianglesCulledFrustum;  // entirely outside the clip volume
          continue;
        }
        ScreenVert sv[kMaxClipVerts];
        bool ok = true;
        for (int i = 0; i < n; ++i) {
          sv[i] = projectClipped(poly + i * kClipStride, vp);
          ok &= (sv[i].flags & kOutGuard) == 0;
        }
        if (!ok) {  // w reached 0: the polygon degenerates to the eye point
          ++st.trianglesCulledDegenerate;
          continue;
        }
        // Chunk-local varyings of the polygon's vertices.
        const uint32_t base = static_cast<uint32_t>(c.clipVary.size() / static_cast<size_t>(stride - 4));
        if (wantAttrs) {
          for (int i = 0; i < n; ++i) {
            const double* p = poly + i * kClipStride;
            for (int c2 = 4; c2 < stride; ++c2) c.clipVary.push_back(static_cast<float>(p[c2]));
          }
        }
        for (int i = 1; i + 1 < n; ++i) {
          const uint32_t ref[3] = {(base + 0) | kChunkLocalVarying, (base + static_cast<uint32_t>(i)) | kChunkLocalVarying,
                                   (base + static_cast<uint32_t>(i) + 1) | kChunkLocalVarying};
          const size_t before = c.tris.size();
          emit(sv[0], sv[i], sv[i + 1], prim, ref, true);
          st.trianglesFromClipping += c.tris.size() - before;
        }
      }

      // Binning: count per tile, prefix sum, fill (CSR).
      c.tileOffsets.assign(numTiles + 1, 0);
      c.tileRect.resize(c.tris.size());
      for (size_t i = 0; i < c.tris.size(); ++i) {
        const SetupTri& t = c.tris[i];
        const uint32_t tx0 = static_cast<uint32_t>(t.minX) >> tileLog2, tx1 = static_cast<uint32_t>(t.maxX) >> tileLog2;
        const uint32_t ty0 = static_cast<uint32_t>(t.minY) >> tileLog2, ty1 = static_cast<uint32_t>(t.maxY) >> tileLog2;
        c.tileRect[i] = uint64_t{tx0} | (uint64_t{tx1} << 16) | (uint64_t{ty0} << 32) | (uint64_t{ty1} << 48);
        for (uint32_t ty = ty0; ty <= ty1; ++ty)
          for (uint32_t tx = tx0; tx <= tx1; ++tx) ++c.tileOffsets[ty * static_cast<uint32_t>(tilesX_) + tx + 1];
      }
      for (uint32_t tIdx = 0; tIdx < numTiles; ++tIdx) c.tileOffsets[tIdx + 1] += c.tileOffsets[tIdx];
      c.entries.resize(c.tileOffsets[numTiles]);
      // Fill: tileOffsets[t] serves as the cursor of tile t.
      for (size_t i = 0; i < c.tris.size(); ++i) {
        const uint64_t rect = c.tileRect[i];
        const auto tx0 = static_cast<uint32_t>(rect & 0xffff), tx1 = static_cast<uint32_t>((rect >> 16) & 0xffff);
        const auto ty0 = static_cast<uint32_t>((rect >> 32) & 0xffff), ty1 = static_cast<uint32_t>(rect >> 48);
        for (uint32_t ty = ty0; ty <= ty1; ++ty)
          for (uint32_t tx = tx0; tx <= tx1; ++tx) {
            const uint32_t tIdx = ty * static_cast<uint32_t>(tilesX_) + tx;
            c.entries[c.tileOffsets[tIdx]++] = static_cast<uint32_t>(i);
          }
      }
      // tileOffsets[t] now holds the end of tile t: shift back to starts.
      for (uint32_t tIdx = numTiles; tIdx > 0; --tIdx) c.tileOffsets[tIdx] = c.tileOffsets[tIdx - 1];
      c.tileOffsets[0] = 0;
      st.trianglesBinned = c.tris.size();
      st.binEntries = c.entries.size();
    }
  });
  for (size_t ci = 0; ci < chunkCount_; ++ci) stats += chunks_[ci].stats;
}

void Rasterizer::tileStage(const DrawDesc& desc, DepthTarget& depth, FragmentSink sink, void* user) {
  const int tileSize = 1 << config_.tileLog2;
  const int numTiles = tilesX_ * tilesY_;
  tbb::parallel_for(tbb::blocked_range<int>(0, numTiles, 1), [&](const tbb::blocked_range<int>& r) {
    detail::TileScratch& s = scratch_.local();
    for (int tIdx = r.begin(); tIdx != r.end(); ++tIdx) {
      PassStats& st = tileStats_[static_cast<size_t>(tIdx)];
      s.tris.clear();
      s.chunkOf.clear();
      s.hits.clear();
      for (size_t ci = 0; ci < chunkCount_; ++ci) {
        const detail::Chunk& c = chunks_[ci];
        const uint32_t b = c.tileOffsets[static_cast<size_t>(tIdx)], e = c.tileOffsets[static_cast<size_t>(tIdx) + 1];
        for (uint32_t k = b; k < e; ++k) {
          s.tris.push_back(&c.tris[c.entries[k]]);
          s.chunkOf.push_back(static_cast<uint32_t>(ci));
        }
      }
      if (s.tris.empty()) continue;
      st.tilesTouched = 1;
      TileJob job;
      job.x0 = (tIdx % tilesX_) * tileSize;
      job.y0 = (tIdx / tilesX_) * tileSize;
      job.x1 = std::min(job.x0 + tileSize, depth.width());
      job.y1 = std::min(job.y0 + tileSize, depth.height());
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
      rasterizeTile(job, st);
      if (sink) sink(user, s, *this);
    }
  });
}

}  // namespace penumbra::raster
