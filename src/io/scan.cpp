#include "io/scan.h"

namespace s2p {

const char* toString(ColourSource source) {
  switch (source) {
    case ColourSource::None: return "none";
    case ColourSource::Vertex: return "vertex";
    case ColourSource::Texture: return "texture";
  }
  return "none";
}

}  // namespace s2p
