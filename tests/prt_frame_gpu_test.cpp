// prt_frame_gpu_test.cpp — bad input of the GPU PRT frame (gpu/prt_frame_gpu.h
// PrtFrameRendererGpu; docs/prt-frame.md): clear exceptions, never a GL error
// or a crash. Its numbers are the harness's (prt/frame/gpu against the CPU frame).
#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/constants.h"
#include "gpu/exemplar_volume_gpu.h"
#include "gpu/gl_context.h"
#include "gpu/prt_frame_gpu.h"

namespace ft {
namespace {

class PrtFrameGpuTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ctx_ = GlContext::create(glBackendFromEnv());
    // The smallest consistent scene: one segment in cell 0, a 2 × 2 SSDF, one SG axis, L = 4.
    segments_ = {VolSegment{glm::vec4(0.0f), glm::vec4(1.0f, 0.0f, 0.0f, 0.0f)}};
    ssdf_.assign(4, 0.1f);
    segmentData_ = {glm::vec4(0.0f)};
    weights_ = {0.0f};
    ssTable_.assign(2 * FT_PRT_SS_TABLE_SIZE, 1.0f);
    transfer_.assign(size_t(3) * FT_SH_COEFFS * FT_SH_COEFFS, 0.0f);
    tables_.thetaO = 2;
    tables_.lambdaNodes = 2;
    tables_.cs.assign(size_t(2) * FT_SH_COEFFS * 3, 0.0f);
    tables_.cg.assign(size_t(2) * FT_SH_BANDS, 0.0f);
  }
  PrtFrameGpuInputs inputs() const {
    PrtFrameGpuInputs in;
    in.segments = segments_;
    in.ssdf = ssdf_;
    in.svfSize = 2;
    in.segmentData = segmentData_;
    in.weights = weights_;
    in.axes = 1;
    in.lambdaSvf = 128.0f;
    in.ssTable = ssTable_;
    in.transfer = transfer_;
    in.bands = 5;
    in.msTables = &tables_;
    return in;
  }
  static VolParams rays(uint32_t camera, uint32_t segments) {
    VolParams p{};
    p.dims = glm::uvec4(4u, 4u, 4u, segments);
    p.ray = glm::uvec4(8u, 8u, 16u, 0u);
    p.camPos = glm::vec4(0.0f, 0.0f, 1.0f, float(camera));
    p.camDir = glm::vec4(0.0f, 0.0f, -1.0f, 0.0f);
    return p;
  }
  std::unique_ptr<GlContext> ctx_;
  std::vector<VolSegment> segments_;
  std::vector<float> ssdf_, weights_, ssTable_, transfer_;
  std::vector<glm::vec4> segmentData_;
  PrtMsGpuTables tables_;
};

TEST_F(PrtFrameGpuTest, RenderBeforeUploadIsALogicError) {
  PrtFrameRendererGpu frame(ctx_->info());
  ExemplarVolumeGpu vol(ctx_->info());
  EXPECT_THROW(frame.render(vol, rays(FT_VOL_CAMERA_ORTHO, 1), glm::vec4(0, 0, 1, 0)), std::logic_error);
}

TEST_F(PrtFrameGpuTest, InconsistentUploadsNameTheirSizes) {
  PrtFrameRendererGpu frame(ctx_->info());
  EXPECT_NO_THROW(frame.upload(inputs()));
  PrtFrameGpuInputs in = inputs();
  in.svfSize = 3;  // 9 SSDF values per segment expected, 4 given
  try {
    frame.upload(in);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("4 SSDF values (3²)"), std::string::npos) << e.what();
  }
  in = inputs();
  in.msTables = nullptr;
  EXPECT_THROW(frame.upload(in), std::invalid_argument);
  in = inputs();
  in.bands = FT_SH_BANDS + 1;
  EXPECT_THROW(frame.upload(in), std::invalid_argument);
  const std::vector<glm::vec4> badCell = {glm::vec4(0.0f, 1.0f, 0.0f, 0.0f)};  // cell 1 of 1
  in = inputs();
  in.segmentData = badCell;
  try {
    frame.upload(in);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("segment 0: cell 1 of 1"), std::string::npos) << e.what();
  }
}

TEST_F(PrtFrameGpuTest, APinholeCameraOrAnotherBlockIsRefused) {
  PrtFrameRendererGpu frame(ctx_->info());
  ExemplarVolumeGpu vol(ctx_->info());
  frame.upload(inputs());
  EXPECT_THROW(frame.render(vol, rays(FT_VOL_CAMERA_PINHOLE, 1), glm::vec4(0, 0, 1, 0)), std::invalid_argument);
  EXPECT_THROW(frame.render(vol, rays(FT_VOL_CAMERA_ORTHO, 2), glm::vec4(0, 0, 1, 0)), std::invalid_argument);
}

}  // namespace
}  // namespace ft
