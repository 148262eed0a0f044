// SPDX-License-Identifier: GPL-3.0-or-later
// Writes the default MeshLab script (.mlx) of every filter of both plugins, from their filter
// tables: `canonform_mlx CANONICAL_DIR VIEWDESCRIPTOR_DIR`. The shipped scripts in
// filter_canonical/scripts and filter_viewdescriptor/scripts are its output (tests/
// test_filter_table.cpp checks that they have not drifted from the tables).
#include "canonical_filter_table.h"
#include "view_filter_table.h"

#include <fstream>
#include <iostream>

namespace {

bool write_all(const std::vector<canonform::meshlab::FilterSpec>& table, const std::string& dir) {
    for (const auto& f : table) {
        const std::string path = dir + "/" + f.script_file();
        std::ofstream out(path);
        out << canonform::meshlab::default_script(f);
        if (!out) {
            std::cerr << "canonform_mlx: cannot write " << path << "\n";
            return false;
        }
        std::cout << path << "\n";
    }
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::cerr << "usage: canonform_mlx CANONICAL_DIR VIEWDESCRIPTOR_DIR\n";
        return 2;
    }
    return write_all(canonform::meshlab::filter_table(), argv[1]) &&
                   write_all(canonform::meshlab::view_filter_table(), argv[2])
               ? 0
               : 1;
}
