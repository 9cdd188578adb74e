// info, convert, preview: the commands that read one scan and report or rewrite it.
#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "app/commands.h"
#include "io/read_scan.h"

namespace s2p::app {

void addScanCommands(CLI::App& app, Commands& out) {
  {
    struct Opt {
      std::string path;
      bool json = false;
      LoadOptions load;
    };
    auto o = std::make_shared<Opt>();
    auto* cmd = app.add_subcommand("info", "Read a scan, clean and normalise it, print a summary");
    cmd->add_option("SCAN", o->path, "Scan file: .obj (+.mtl, texture), .ply, .gltf, .glb")
        ->required();
    cmd->add_flag("--json", o->json, "Print the summary as JSON");
    addLoadOptions(cmd, o->load);
    out.push_back({cmd, [o](Progress& progress) {
                     Progress& p = o->json ? Progress::silent() : progress;
                     const LoadedScan s = loadScan(o->path, o->load, p);
                     const nlohmann::json j = infoJson(s);
                     if (o->json)
                       std::cout << j.dump(2) << "\n";
                     else
                       printInfo(j);
                     return 0;
                   }});
  }
  {
    struct Opt {
      std::string in, out;
      bool keepFrame = false;
      LoadOptions load;
    };
    auto o = std::make_shared<Opt>();
    auto* cmd =
        app.add_subcommand("convert", "Read, clean and normalise a scan, then write it out");
    cmd->add_option("SCAN", o->in, "Input scan file")->required();
    cmd->add_option("OUT", o->out, "Output mesh: .ply, .obj or .glb")->required();
    cmd->add_flag("--input-frame", o->keepFrame,
                  "Write in the input's units and axes instead of metres, +Y up");
    addLoadOptions(cmd, o->load);
    out.push_back({cmd, [o](Progress& progress) {
                     LoadedScan s = loadScan(o->in, o->load, progress);
                     TriMesh mesh = s.scan.mesh;
                     if (o->keepFrame)
                       mesh.V = (s.scan.toInputFrame * mesh.V.transpose()).transpose();
                     writeMesh(o->out, mesh, colourAttributes(s.scan));
                     progress.message(fmt::format("wrote {} ({} vertices, {} faces)", o->out,
                                                  mesh.numVertices(), mesh.numFaces()));
                     return 0;
                   }});
  }
  {
    struct Opt {
      std::string in, out, views = "front";
      int height = 1024;
      bool asIs = false;
      LoadOptions load;
    };
    auto o = std::make_shared<Opt>();
    auto* cmd = app.add_subcommand("preview", "Render a mesh to a PNG picture");
    cmd->add_option("MESH", o->in, "Mesh or scan file")->required();
    cmd->add_option("-o,--output", o->out, "Output PNG")->required();
    cmd->add_option("--views", o->views, "Comma-separated: front, back, left, right, three-quarter")
        ->capture_default_str();
    cmd->add_option("--height", o->height, "Image height in pixels")
        ->capture_default_str()
        ->check(CLI::Range(64, 8192));
    cmd->add_flag("--as-is", o->asIs,
                  "Render the file's mesh as it is (metres, +Y up), without the clean-up and the "
                  "checks that it is a person: for panels.obj, draped.obj, unsettled.obj");
    addLoadOptions(cmd, o->load);
    out.push_back({cmd, [o](Progress& progress) {
                     const std::vector<View> views = parseViews(o->views);
                     const Scan scan = [&] {
                       if (!o->asIs) return loadScan(o->in, o->load, progress).scan;
                       progress.begin("read " + o->in);
                       Scan raw = readScan(o->in);
                       progress.end();
                       return raw;
                     }();
                     progress.begin("render");
                     writePng(o->out, renderScan(scan, views, o->height));
                     progress.end();
                     progress.message("wrote " + o->out);
                     return 0;
                   }});
  }
}

}  // namespace s2p::app
