// A list of block (or region) ids and the indirect arguments that run one workgroup per entry,
// a mesh-task draw or a compute dispatch: the header of every such list, mirrored by
// `iso::direct::block_list::BlockListHeader`. Writers count entries in `count`; either a pass
// after them turns the count into `args`, or they grow `args` as they append
// (common/indirect_args.glsl).
struct BlockListHeader {
    uint count;
    uint args[3];
};
