#include "cli/viewer_panel.hpp"

#include "present/gl.hpp"  // before GLFW, which must not pull in the legacy GL header
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <fmt/format.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <span>

#include "core/camera.hpp"
#include "csm/visibility.hpp"
#include "runtime/error.hpp"

namespace splatcl::cli::viewer {

glm::vec3 heat_color(float t) {
  // heat() of present/shaders/shade.frag.glsl: the same expression.
  t = std::clamp(t, 0.0f, 1.0f);
  return glm::clamp(glm::vec3(1.5f * t - 0.25f, 1.5f - std::abs(2.0f * t - 1.0f) * 1.5f, 1.25f - 1.5f * t), 0.0f, 1.0f);
}

namespace {

ImU32 color_u32(const glm::vec3& c) { return ImGui::ColorConvertFloat4ToU32(ImVec4(c.x, c.y, c.z, 1.0f)); }

// Radio buttons over a sequence of strings; true when one was chosen.
bool choice(const char* label, std::string& value, std::span<const char* const> values) {
  bool changed = false;
  ImGui::TextUnformatted(label);
  for (const char* v : values) {
    ImGui::SameLine();
    if (ImGui::RadioButton(fmt::format("{}##{}", v, label).c_str(), value == v)) value = v, changed = true;
  }
  return changed;
}
bool choice(const char* label, std::string& value, std::initializer_list<const char*> values) {
  return choice(label, value, std::span<const char* const>(values.begin(), values.size()));
}

// A checkbox for "value > 0" (on sets `on`, off sets 0) and, while on, a slider for the value.
void toggle_with_slider(const char* label, const char* slider, float& value, float on, float lo, float hi) {
  bool enabled = value > 0;
  if (ImGui::Checkbox(label, &enabled)) value = enabled ? on : 0.0f;
  if (!enabled) return;
  ImGui::SameLine();
  ImGui::SetNextItemWidth(120);
  ImGui::SliderFloat(slider, &value, lo, hi, "%.2f", ImGuiSliderFlags_Logarithmic);
}

void heat_legend(const present::FrameStats& stats) {
  ImGui::TextUnformatted("lights per cluster (view 5, clusters):");
  const ImVec2 p = ImGui::GetCursorScreenPos();
  const float width = std::max(120.0f, ImGui::GetContentRegionAvail().x), height = 14;
  ImDrawList* draw = ImGui::GetWindowDrawList();
  constexpr int kSteps = 32;
  for (int i = 0; i < kSteps; ++i) {
    const float t0 = static_cast<float>(i) / kSteps, t1 = static_cast<float>(i + 1) / kSteps;
    const ImU32 a = color_u32(heat_color(t0)), b = color_u32(heat_color(t1));
    draw->AddRectFilledMultiColor(ImVec2(p.x + t0 * width, p.y), ImVec2(p.x + t1 * width, p.y + height), a, b, b, a);
  }
  ImGui::Dummy(ImVec2(width, height));
  ImGui::TextUnformatted("0");
  ImGui::SameLine(width * 0.5f - 20);
  ImGui::Text("%.1f", 0.5 * stats.heat_max);
  ImGui::SameLine(std::max(width - 70, width * 0.5f + 20));
  ImGui::Text("%u (max)", stats.heat_max);
  if (stats.clusters > 0)
    ImGui::Text("mean %.1f lights in each of %u clusters", static_cast<double>(stats.light_indices) / stats.clusters, stats.clusters);
  else  // brute-force shading builds none, and its map is uniform at the top (a helper took it for a fault)
    ImGui::TextUnformatted("no clusters this frame; brute-force shading takes every light at every pixel");
}

}  // namespace

Panel::Panel(GLFWwindow* window) : window_(window) {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // no imgui.ini in the working directory
  ImGui::StyleColorsDark();
  // Opaque and square: the panel window's rectangle is then copied into the window (a blit),
  // which llvmpipe does far faster than blending it.
  ImGuiStyle& style = ImGui::GetStyle();
  style.WindowRounding = 0;
  style.Colors[ImGuiCol_WindowBg].w = 1.0f;
  ImGui_ImplGlfw_InitForOpenGL(window_, false);
  ImGui_ImplOpenGL3_Init("#version 410");
  // The compositing program: a triangle over the whole frame that reads the layer texel by texel.
  const char* vs = "#version 450 core\nvoid main() { vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);\n"
                   "gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0); }\n";
  const char* fs = "#version 450 core\nlayout(binding = 0) uniform sampler2D u_layer; out vec4 o_color;\n"
                   "void main() { o_color = texelFetch(u_layer, ivec2(gl_FragCoord.xy), 0); }\n";
  program_ = glCreateProgram();
  for (const auto& [type, text] : {std::pair{GL_VERTEX_SHADER, vs}, std::pair{GL_FRAGMENT_SHADER, fs}}) {
    const GLuint shader = glCreateShader(type);
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) throw Error("the viewer panel's compositing shader does not compile");
    glAttachShader(program_, shader);
    glDeleteShader(shader);
  }
  glLinkProgram(program_);
  GLint linked = 0;
  glGetProgramiv(program_, GL_LINK_STATUS, &linked);
  if (!linked) throw Error("the viewer panel's compositing program does not link");
  glCreateVertexArrays(1, &vertex_array_);
}

Panel::~Panel() {
  if (framebuffer_) glDeleteFramebuffers(1, &framebuffer_);
  if (texture_) glDeleteTextures(1, &texture_);
  if (vertex_array_) glDeleteVertexArrays(1, &vertex_array_);
  if (program_) glDeleteProgram(program_);
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

GlfwInput::Hooks Panel::hooks() const {
  GlfwInput::Hooks h;
  h.key = [](GLFWwindow* w, int key, int scancode, int action, int mods) { ImGui_ImplGlfw_KeyCallback(w, key, scancode, action, mods); };
  h.character = [](GLFWwindow* w, unsigned c) { ImGui_ImplGlfw_CharCallback(w, c); };
  h.button = [](GLFWwindow* w, int button, int action, int mods) { ImGui_ImplGlfw_MouseButtonCallback(w, button, action, mods); };
  h.scroll = [](GLFWwindow* w, double dx, double dy) { ImGui_ImplGlfw_ScrollCallback(w, dx, dy); };
  h.cursor = [this](GLFWwindow*, double x, double y) {
    polled_cursor_[0] = x, polled_cursor_[1] = y;
    have_polled_cursor_ = true;
  };
  h.enter = [](GLFWwindow* w, int entered) { ImGui_ImplGlfw_CursorEnterCallback(w, entered); };
  h.focus = [](GLFWwindow* w, int focused) { ImGui_ImplGlfw_WindowFocusCallback(w, focused); };
  // The keyboard: ImGui's flag of its last frame (draw() clears it while the panel is hidden). The
  // mouse: that flag (a slider dragged off the panel) or the cursor over the panel as last drawn,
  // since a move onto the panel and a click can come within one frame, before ImGui sees the move.
  h.captured = [this](bool keyboard) {
    const ImGuiIO& io = ImGui::GetIO();
    if (keyboard) return io.WantCaptureKeyboard;
    if (io.WantCaptureMouse) return true;
    if (!have_layer_) return false;
    double x = polled_cursor_[0], y = polled_cursor_[1];
    if (!have_polled_cursor_) glfwGetCursorPos(window_, &x, &y);
    return x >= window_min_[0] && x < window_max_[0] && y >= window_min_[1] && y < window_max_[1];
  };
  return h;
}

void Panel::build(Controls& controls, const present::FrameStats& stats, const std::vector<ObjectFigures>& objects, float time) {
  tooltip_ = false;
  ViewState& v = controls.state();
  splatcl::Scene& s = controls.scene();
  splatcl::Quality& q = s.quality;

  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGuiIO& io = ImGui::GetIO();
  if (have_polled_cursor_ && io.MousePos.x != -FLT_MAX) io.MousePos = ImVec2(static_cast<float>(polled_cursor_[0]), static_cast<float>(polled_cursor_[1]));
  ImGui::NewFrame();
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(430, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("splatcl view (F1 hides)", nullptr, ImGuiWindowFlags_NoSavedSettings);

  ImGui::Text("%.1f fps  %.1f ms/frame  panel %.2f ms", stats.frame_ms > 0 ? 1000.0 / stats.frame_ms : 0.0, stats.frame_ms, last_ms_);
  ImGui::Text("%u splats drawn, %zu lights, %u clusters, %u light indices", stats.splats, s.lights.size(), stats.clusters,
              stats.light_indices);
  // Always one line, so the widgets below keep their places.
  ImGui::TextUnformatted(v.message.empty() ? "click an object to select it" : v.message.c_str());

  if (ImGui::CollapsingHeader("modes and toggles", ImGuiTreeNodeFlags_DefaultOpen)) {
    choice("shading [C]", q.shading, {"clustered", "tiled", "brute"});
    choice("mode    [M]", q.mode, {"splats", "points"});
    choice("shadows [H]", q.shadows, {"splat", "pixel", "off"});
    choice("shadow test", q.filter, csm::kFilterNames);
    ImGui::Checkbox("ambient occlusion [O]", &v.ambient_occlusion);
    ImGui::SameLine();
    ImGui::Checkbox("per pixel [A]", &v.pixel_ao);
    ImGui::Checkbox("floor's AO and shadows per pixel [G]", &v.floor_pixels);
    toggle_with_slider("silhouette resolve [S]", "depth jump", q.antialias, controls.antialias_on(), 0.01f, 1.0f);
    toggle_with_slider("level of detail [L]", "px##lod", q.lod_error, controls.lod_on(), 0.1f, 16.0f);
    toggle_with_slider("Blinn-Phong [B]", "strength", q.specular, controls.specular_on(), 0.01f, 4.0f);
    static constexpr std::array<const char*, 8> kViews = {"1 final",    "2 albedo",  "3 normals", "4 ao",
                                                          "5 clusters", "6 shadows", "7 depth",   "8 footprints"};
    int view = static_cast<int>(v.debug_view);
    if (ImGui::Combo("debug view [1-8]", &view, kViews.data(), static_cast<int>(kViews.size())))
      v.debug_view = static_cast<present::DebugView>(view);
    ImGui::Checkbox("paused [Space]", &v.paused);
    ImGui::SliderFloat("splat scale k", &q.splat_scale, kMinSplatScale, kMaxSplatScale, "%.3f");
    ImGui::SliderFloat("depth offset eps", &q.depth_offset, 0.0f, 0.2f, "%.4f");
    int lights = static_cast<int>(s.generated.count);
    const int explicit_lights = static_cast<int>(s.lights.size() - s.generated.count);
    if (ImGui::SliderInt("generated lights", &lights, 0, static_cast<int>(splatcl::kMaxSceneLights) - explicit_lights, "%d",
                         ImGuiSliderFlags_Logarithmic))
      splatcl::set_generated_light_count(s, static_cast<std::uint32_t>(std::max(lights, 0)));
    // Generated lights come from "lights": {"count": N}; listed ones from an explicit array.
    ImGui::Text("%zu point lights (%u generated, %d listed), %zu key lights", s.lights.size(), s.generated.count, explicit_lights,
                s.key_lights.size());
  }

  if (ImGui::CollapsingHeader("stages (ms)", ImGuiTreeNodeFlags_DefaultOpen) &&
      ImGui::BeginTable("stages", 3, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp)) {
    double total = 0;
    for (const auto& st : stats.stages) total += st.ms;
    for (const auto& st : stats.stages) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(st.name.c_str());
      ImGui::TableNextColumn();
      ImGui::Text("%8.2f", st.ms);
      ImGui::TableNextColumn();
      ImGui::ProgressBar(total > 0 ? static_cast<float>(st.ms / total) : 0.0f, ImVec2(-1, 0), "");
    }
    ImGui::EndTable();
  }

  if (ImGui::CollapsingHeader("heat map legend", v.debug_view == present::DebugView::LightsPerCluster ? ImGuiTreeNodeFlags_DefaultOpen : 0))
    heat_legend(stats);

  if (ImGui::CollapsingHeader("camera", ImGuiTreeNodeFlags_DefaultOpen)) {
    const Orbit& o = controls.orbit();
    ImGui::Text("distance %.2f  target (%.2f, %.2f, %.2f)", o.distance, o.target.x, o.target.y, o.target.z);
    if (ImGui::Button("fit [F]")) controls.fit(time);
    ImGui::SameLine();
    if (ImGui::Button("reset [R]")) controls.reset_camera();
    ImGui::SameLine();
    if (ImGui::Button("reset objects [Shift+R]")) controls.reset_objects();
  }

  if (ImGui::CollapsingHeader("objects (click one, or Tab)", ImGuiTreeNodeFlags_DefaultOpen) &&
      ImGui::BeginTable("objects", 6, ImGuiTableFlags_RowBg | ImGuiTableFlags_Borders | ImGuiTableFlags_SizingFixedFit)) {
    ImGui::TableSetupColumn("object");
    ImGui::TableSetupColumn("faces");
    ImGui::TableSetupColumn("splats");
    ImGui::TableSetupColumn("LOD");
    ImGui::TableSetupColumn("CSM maps x res^2");
    ImGui::TableSetupColumn("segments, MiB");
    ImGui::TableHeadersRow();
    for (std::size_t i = 0; i < objects.size(); ++i) {
      const ObjectFigures& f = objects[i];
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      if (ImGui::Selectable(fmt::format("{}##object{}", f.name, i).c_str(), v.selected == i, ImGuiSelectableFlags_SpanAllColumns))
        v.selected = i;
      if (ImGui::IsItemHovered()) {
        tooltip_ = true;
        ImGui::SetTooltip("%s; %s%s, %zu vertices; splats %s, %zu gap splats %s, fit to the surface %s, LOD tree %s, normal fields %s, CSM %s (single hit %s); assets %.0f ms; cache key %s",
                          f.source.c_str(), f.occluder ? "occluder" : "not an occluder", f.two_sided ? ", two-sided" : "", f.vertices, f.splats_cached ? "cached" : "built",
                          f.gap_splats, f.gaps_cached ? "cached" : "built", f.drawn_cached ? "cached" : "not cached", f.tree_cached ? "cached" : "built",
                          f.fields_cached ? "cached" : "not cached", f.csm_cached ? "cached" : "built", f.csm_single_hit.c_str(), f.build_ms, f.key.c_str());
      }
      ImGui::TableNextColumn();
      ImGui::Text("%zu", f.faces);
      ImGui::TableNextColumn();
      ImGui::Text("%zu", f.splats);
      ImGui::TableNextColumn();
      ImGui::Text("%zu", f.lod_entries);
      ImGui::TableNextColumn();
      ImGui::Text("%u x %u^2", f.csm_maps, f.csm_resolution);
      ImGui::TableNextColumn();
      ImGui::Text("%zu (%.2f/px), %.1f", f.csm_segments, f.csm_segments_per_pixel, static_cast<double>(f.csm_bytes) / (1 << 20));
    }
    ImGui::EndTable();
  }
  const ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
  window_min_[0] = pos.x, window_min_[1] = pos.y, window_max_[0] = pos.x + size.x, window_max_[1] = pos.y + size.y;
  ImGui::End();
  ImGui::Render();
}

void Panel::resize_layer(int width, int height) {
  if (texture_ && width == layer_width_ && height == layer_height_) return;
  if (framebuffer_) glDeleteFramebuffers(1, &framebuffer_);
  if (texture_) glDeleteTextures(1, &texture_);
  glCreateTextures(GL_TEXTURE_2D, 1, &texture_);
  glTextureStorage2D(texture_, 1, GL_RGBA8, width, height);
  glCreateFramebuffers(1, &framebuffer_);
  glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0, texture_, 0);
  layer_width_ = width, layer_height_ = height, have_layer_ = false;
}

void Panel::draw(Controls& controls, const present::FrameStats& stats, const std::vector<ObjectFigures>& objects, float time, int width,
                 int height, bool refresh) {
  refreshed_ = false;
  if (!controls.state().panel || width <= 0 || height <= 0) {
    // Hidden: no frame, and nothing captured from then on.
    ImGuiIO& io = ImGui::GetIO();
    io.WantCaptureKeyboard = io.WantCaptureMouse = false;
    last_ms_ = 0;
    have_layer_ = false;  // shown again: a fresh frame first
    return;
  }
  // Timed with the GL work it queues: the blit before it finished first, its own drawing after
  // (llvmpipe would otherwise rasterise it inside the buffer swap, out of sight).
  glFinish();
  const auto start = std::chrono::steady_clock::now();
  resize_layer(width, height);
  if (refresh || !have_layer_) {
    build(controls, stats, objects, time);
    // The layer: premultiplied colour and coverage (the backend blends colour by alpha and alpha
    // by one minus alpha), transparent where the panel is not.
    // The layer holds pixels only inside rect_ (the last refresh's): clearing that clears it.
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer_);
    const float clear[4] = {0, 0, 0, 0};
    glEnable(GL_SCISSOR_TEST);
    if (have_layer_) glScissor(rect_[0], rect_[1], rect_[2], rect_[3]);
    else glScissor(0, 0, width, height);
    glClearNamedFramebufferfv(framebuffer_, GL_COLOR, 0, clear);
    glDisable(GL_SCISSOR_TEST);
    ImDrawData* data = ImGui::GetDrawData();
    ImGui_ImplOpenGL3_RenderDrawData(data);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    // The panel window's rectangle in framebuffer pixels (bottom-left origin); the whole frame
    // while a tooltip, which lies outside it, is up.
    const ImVec2 scale = data->FramebufferScale, origin = data->DisplayPos;
    const float x0 = tooltip_ ? origin.x : window_min_[0], y0 = tooltip_ ? origin.y : window_min_[1];
    const float x1 = tooltip_ ? origin.x + data->DisplaySize.x : window_max_[0], y1 = tooltip_ ? origin.y + data->DisplaySize.y : window_max_[1];
    const int left = std::clamp(static_cast<int>(std::floor((x0 - origin.x) * scale.x)), 0, width);
    const int right = std::clamp(static_cast<int>(std::ceil((x1 - origin.x) * scale.x)) + 1, 0, width);
    const int top = std::clamp(static_cast<int>(std::floor((y0 - origin.y) * scale.y)), 0, height);
    const int bottom = std::clamp(static_cast<int>(std::ceil((y1 - origin.y) * scale.y)) + 1, 0, height);
    rect_[0] = left, rect_[1] = height - bottom, rect_[2] = std::max(0, right - left), rect_[3] = std::max(0, bottom - top);
    have_layer_ = true, refreshed_ = true;
  }
  if (rect_[2] > 0 && rect_[3] > 0 && !tooltip_) {
    // The opaque panel window: copied.
    glBlitNamedFramebuffer(framebuffer_, 0, rect_[0], rect_[1], rect_[0] + rect_[2], rect_[1] + rect_[3], rect_[0], rect_[1],
                           rect_[0] + rect_[2], rect_[1] + rect_[3], GL_COLOR_BUFFER_BIT, GL_NEAREST);
  } else if (rect_[2] > 0 && rect_[3] > 0) {
    // With a tooltip outside the window: the whole layer blended over the frame (premultiplied alpha).
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glViewport(0, 0, width, height);
    glEnable(GL_SCISSOR_TEST);
    glScissor(rect_[0], rect_[1], rect_[2], rect_[3]);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glUseProgram(program_);
    glBindTextureUnit(0, texture_);
    glBindVertexArray(vertex_array_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glUseProgram(0);
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
  }
  glFinish();
  last_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace splatcl::cli::viewer
