#version 460
// A proxy fragment that passed the depth test marks its region visible. Early tests make the
// depth test happen before this write.
layout(early_fragment_tests) in;
layout(location = 0) flat in uint region_id;
layout(binding = 1) writeonly buffer Visible { uint visible[]; };

void main() {
    visible[region_id] = 1u;
}
