//! The GPU the preview draws on: a wgpu device and queue, found headless (a hardware adapter if
//! there is one, else a software one such as Mesa's lavapipe or llvmpipe) or handed in by an
//! application that already has one (the studio).

use crate::PreviewError;

/// A wgpu device with its queue and a description of the adapter.
#[derive(Clone, Debug)]
pub struct Gpu {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// What the adapter is (name, backend, whether it is a CPU).
    pub info: wgpu::AdapterInfo,
}

impl Gpu {
    /// A device for offscreen drawing, with no window: the best adapter of Vulkan, Metal, DX12
    /// or GL, a software one when there is no GPU.
    ///
    /// ```no_run
    /// let gpu = orbifold_preview::Gpu::headless()?;
    /// println!("{} ({:?})", gpu.info.name, gpu.info.device_type);
    /// # Ok::<(), orbifold_preview::PreviewError>(())
    /// ```
    pub fn headless() -> Result<Gpu, PreviewError> {
        pollster::block_on(Self::request())
    }

    /// A device made by someone else (an application's window), for the preview to share.
    pub fn from_parts(device: wgpu::Device, queue: wgpu::Queue, info: wgpu::AdapterInfo) -> Gpu {
        Gpu {
            device,
            queue,
            info,
        }
    }

    async fn request() -> Result<Gpu, PreviewError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::from_env()
                .unwrap_or(wgpu::Backends::PRIMARY | wgpu::Backends::GL),
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                ..Default::default()
            })
            .await
            .map_err(|e| {
                PreviewError::NoAdapter(format!(
                    "{e}; install a GPU driver, or Mesa's software Vulkan driver \
                     (Debian: mesa-vulkan-drivers libvulkan1)"
                ))
            })?;
        let info = adapter.get_info();
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("orbifold preview"),
                // Everything the adapter can: big scenes need big buffers.
                required_limits: adapter.limits(),
                ..Default::default()
            })
            .await
            .map_err(|e| PreviewError::NoAdapter(format!("{}: {e}", info.name)))?;
        Ok(Gpu {
            device,
            queue,
            info,
        })
    }

    /// One line about the adapter: its name, kind and backend.
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {:?})",
            self.info.name, self.info.device_type, self.info.backend
        )
    }
}
