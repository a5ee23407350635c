use tessera_data::DataError;
use tessera_gpu::GpuError;

/// Errors from the techniques: a GPU or data problem, or a request that makes no sense.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error(transparent)]
    Gpu(#[from] GpuError),
    #[error(transparent)]
    Data(#[from] DataError),
    #[error("{0}")]
    Invalid(String),
}

pub type Result<T> = std::result::Result<T, Error>;
