//! Telling file formats apart by their first bytes, for files whose extension does not say
//! what they hold (a mesh saved as `.dat`, a volume as `.xml`), so that they reach the right
//! loader instead of being taken for raw volume data.

use std::io::Read;
use std::path::Path;

/// A format recognised by its content.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sniffed {
    /// `# vtk DataFile` (legacy VTK, read as a tetrahedral mesh).
    LegacyVtk,
    /// `<VTKFile type="UnstructuredGrid"`.
    VtkXmlMesh,
    /// `<VTKFile type="ImageData"`.
    VtkXmlImage,
    /// `$MeshFormat` (Gmsh).
    Gmsh,
    /// `NRRD000x`.
    Nrrd,
}

impl Sniffed {
    /// Whether the format holds a tetrahedral mesh (else a volume).
    pub fn is_mesh(self) -> bool {
        matches!(
            self,
            Sniffed::LegacyVtk | Sniffed::VtkXmlMesh | Sniffed::Gmsh
        )
    }

    /// The format in words, for messages.
    pub fn describe(self) -> &'static str {
        match self {
            Sniffed::LegacyVtk => "a legacy VTK file",
            Sniffed::VtkXmlMesh => "a VTK XML unstructured grid",
            Sniffed::VtkXmlImage => "VTK XML image data",
            Sniffed::Gmsh => "a Gmsh mesh",
            Sniffed::Nrrd => "a NRRD volume",
        }
    }
}

/// How far into a file the signatures are looked for (XML files may open with a
/// declaration and comments before `<VTKFile`).
const HEAD: u64 = 4096;

/// The format of the file at `path` as its first bytes say; `None` when they name none of
/// the formats above or the file cannot be read (the loader then reports that).
pub fn sniff(path: &Path) -> Option<Sniffed> {
    let mut head = Vec::new();
    std::fs::File::open(path)
        .ok()?
        .take(HEAD)
        .read_to_end(&mut head)
        .ok()?;
    sniff_bytes(&head)
}

/// The format the first bytes of a file name.
pub fn sniff_bytes(head: &[u8]) -> Option<Sniffed> {
    let text = String::from_utf8_lossy(head);
    let start = text.trim_start_matches('\u{feff}').trim_start();
    let magic = b"# vtk datafile";
    if start
        .as_bytes()
        .get(..magic.len())
        .is_some_and(|b| b.eq_ignore_ascii_case(magic))
    {
        return Some(Sniffed::LegacyVtk);
    }
    if start.starts_with("$MeshFormat") {
        return Some(Sniffed::Gmsh);
    }
    if start.starts_with("NRRD000") {
        return Some(Sniffed::Nrrd);
    }
    let root = start.find("<VTKFile")?;
    let tag = &start[root..start[root..].find('>').map_or(start.len(), |e| root + e)];
    if tag.contains("\"UnstructuredGrid\"") || tag.contains("'UnstructuredGrid'") {
        Some(Sniffed::VtkXmlMesh)
    } else if tag.contains("\"ImageData\"") || tag.contains("'ImageData'") {
        Some(Sniffed::VtkXmlImage)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signatures() {
        let cases: [(&[u8], Option<Sniffed>); 8] = [
            (b"# vtk DataFile Version 3.0\n", Some(Sniffed::LegacyVtk)),
            (b"$MeshFormat\n4.1 0 8\n", Some(Sniffed::Gmsh)),
            (b"NRRD0004\ntype: uint8\n", Some(Sniffed::Nrrd)),
            (
                b"<?xml version=\"1.0\"?>\n<!-- x -->\n<VTKFile type=\"UnstructuredGrid\">",
                Some(Sniffed::VtkXmlMesh),
            ),
            (
                b"<VTKFile type='ImageData' version='1.0'>",
                Some(Sniffed::VtkXmlImage),
            ),
            (b"<VTKFile type=\"PolyData\">", None),
            (b"\x00\x01\x02\x03", None),
            (b"", None),
        ];
        for (head, want) in cases {
            assert_eq!(
                sniff_bytes(head),
                want,
                "{:?}",
                String::from_utf8_lossy(head)
            );
        }
    }
}
