// The MTL files an OBJ names with `mtllib`, read by rayspace for tinyobjloader: only bounded
// regular files (input_file.h), line ends normalised as for the OBJ, and every value the loader
// uses or tinyobjloader reads as a number checked before tinyobjloader parses it.
#pragma once
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <tiny_obj_loader.h>

namespace rayspace {

// Looks `mtllib` names up beside the OBJ (an absolute name is used as is). A missing file is a
// warning, as tinyobjloader makes it; a file that exists but cannot be read, or holds a bad value,
// is an InputError naming the MTL file, its line and key.
class MtlFiles : public tinyobj::MaterialReader {
 public:
  explicit MtlFiles(const std::filesystem::path& obj);
  bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* by_name, std::string* warn, std::string* err) override;

 private:
  std::filesystem::path dir_;
  std::string what_;
};

// Checks every numeric MTL line (normalised line ends) against its accepted range; throws naming
// file, line and key.
void ValidateMtlText(const std::string& file, const std::string& text);

}  // namespace rayspace
