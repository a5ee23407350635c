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

/// Refuses empty images before any GPU object is made for them.
pub fn check_image_size(width: u32, height: u32) -> Result<()> {
    if width == 0 || height == 0 {
        return Err(Error::Invalid(format!(
            "image size {width}x{height} is empty"
        )));
    }
    Ok(())
}
