#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use tessera_data::nifti;

fuzz_target!(|data: &[u8]| {
    let file = "input.nii";
    let result = nifti::parse_components_bytes(data, common::path(file));
    common::names_file(&result, file);
    if let Ok(v) = result {
        // Every voxel's components are reachable.
        let [nx, ny, nz] = v.dims;
        if nx > 0 && ny > 0 && nz > 0 {
            let _ = v.voxel(nx - 1, ny - 1, nz - 1);
        }
    }
});
