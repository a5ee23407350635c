// Task-to-mesh payload of the meshlet draw: the meshlets of one task workgroup that passed
// culling, one mesh workgroup each.
struct MeshletDrawPayload {
    uint meshlet_ids[MESHLET_DRAW_TASK_SIZE];
};
taskPayloadSharedEXT MeshletDrawPayload payload;
