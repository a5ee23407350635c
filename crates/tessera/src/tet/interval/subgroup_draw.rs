//! Which tets the per-tet pass's subgroups draw together (`subgroup_draw.glsl`), and the
//! defines that tell the shader.

/// Which tets the per-tet pass's subgroups draw together, all invocations of a subgroup taking
/// the pixels of one tet after another, where the device has subgroup ballot, shuffle and
/// arithmetic (elsewhere each invocation draws its own tet). The image is the same every way.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SubgroupDraw {
    /// Each invocation draws its own tet.
    Off,
    /// The tets whose screen rectangle holds more than this many pixels; each invocation
    /// draws the smaller ones itself.
    Above(u32),
    /// Each subgroup takes the limit of [`SUBGROUP_DRAW_CHOICES`] whose estimated time is least:
    /// the largest rectangle one of its invocations draws alone, plus, for each tet drawn
    /// together, `setup_pixels` and its rectangle's pixels spread over the subgroup.
    Chosen { setup_pixels: u32 },
}

impl Default for SubgroupDraw {
    fn default() -> Self {
        SubgroupDraw::Above(SUBGROUP_DRAW_ABOVE_PIXELS)
    }
}

impl SubgroupDraw {
    pub fn name(self) -> String {
        match self {
            SubgroupDraw::Off => "subgroup drawing off".into(),
            SubgroupDraw::Above(pixels) => format!("subgroup drawing above {pixels} px"),
            SubgroupDraw::Chosen { setup_pixels } => {
                format!("subgroup drawing chosen (set-up {setup_pixels} px)")
            }
        }
    }
}

/// The per-tet pass's subgroups draw together only the tets whose screen rectangle holds more
/// pixels than this. A subgroup draws its tets one after another, each at least one step of
/// all its invocations, so for small tets it spends its time setting up one tet after another
/// while each invocation alone would have drawn its own few pixels. On the H200 at 1920×1080
/// the 2.4 M-tet box far went from 5.38 to 3.24 ms (scalar field 4.73 to 3.59), and the other
/// 46 per-tet cells (the 2.4 M, 584 k and 64 k-tet boxes and the bunny, far, close and inside,
/// 1920×1080 and 3840×2160, both integrands) stayed within 1.1 % (run 116). A limit of 256
/// gained more there (2.48 ms) but lost 1.6–4.6 % on six cells (the bunny far and the 584 k
/// box close at 1920×1080, the 2.4 M box far at 3840×2160).
pub const SUBGROUP_DRAW_ABOVE_PIXELS: u32 = 64;

/// The limits [`SubgroupDraw::Chosen`] chooses among, per subgroup.
pub const SUBGROUP_DRAW_CHOICES: [u32; 4] = [64, 256, 1024, 4096];

/// The defines of the per-tet pass's subgroup drawing (`subgroup_draw.glsl`): none
/// (`INTERVAL_SUBGROUP_DRAW` 0), the tets above a fixed number of pixels of their screen
/// rectangle (`SUBGROUP_DRAW_ABOVE_PIXELS`), or above the limit of `SUBGROUP_DRAW_LIMITS` each
/// subgroup chooses (`SUBGROUP_DRAW_CHOSEN` 1, a shared tet costing
/// `SUBGROUP_DRAW_SETUP_PIXELS` beyond its pixels).
pub(crate) fn subgroup_draw_defines(way: SubgroupDraw) -> Vec<(String, String)> {
    let (above, chosen, setup) = match way {
        SubgroupDraw::Off => (0, false, 0),
        SubgroupDraw::Above(pixels) => (pixels, false, 0),
        SubgroupDraw::Chosen { setup_pixels } => (0, true, setup_pixels),
    };
    let limits: Vec<String> = SUBGROUP_DRAW_CHOICES
        .iter()
        .map(|l| format!("{l}u"))
        .collect();
    vec![
        (
            "INTERVAL_SUBGROUP_DRAW".into(),
            u32::from(way != SubgroupDraw::Off).to_string(),
        ),
        ("SUBGROUP_DRAW_ABOVE_PIXELS".into(), format!("{above}u")),
        ("SUBGROUP_DRAW_CHOSEN".into(), u32::from(chosen).to_string()),
        ("SUBGROUP_DRAW_SETUP_PIXELS".into(), format!("{setup}u")),
        (
            "SUBGROUP_DRAW_LIMITS".into(),
            format!("uint[]({})", limits.join(", ")),
        ),
    ]
}
