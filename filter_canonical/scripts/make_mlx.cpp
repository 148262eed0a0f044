// Writes the default MeshLab script (.mlx) of every filter of filter_canonical into a folder,
// from the filter table: `canonform_mlx DIR`. The shipped scripts in this folder are its output
// (tests/test_filter_table.cpp checks that they have not drifted from the table).
#include "filter_table.h"

#include <fstream>
#include <iostream>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: canonform_mlx OUTPUT_DIR\n";
        return 2;
    }
    for (const auto& f : canonform::plugin::filter_table()) {
        const std::string path = std::string(argv[1]) + "/" + f.script_file;
        std::ofstream out(path);
        out << canonform::plugin::default_script(f);
        if (!out) {
            std::cerr << "canonform_mlx: cannot write " << path << "\n";
            return 1;
        }
        std::cout << path << "\n";
    }
    return 0;
}
