//! C++'s `operator new(size_t)` and `operator delete(void*)` for meshoptimizer (the preview's
//! vertex-cache optimiser, C++ compiled by the meshopt crate): on `wasm32-unknown-unknown`
//! there is no C++ runtime to provide them, and the module would import them from the page
//! (`env._Znwm`, `env._ZdlPv`), which cannot load. They allocate through Rust's allocator,
//! with the size kept in front of the block for `delete`.

#![allow(unsafe_code)]

use std::alloc::{Layout, alloc, dealloc, handle_alloc_error};

/// Room kept in front of each block for its size; also the blocks' alignment, as C++'s
/// `operator new` guarantees alignment for any fundamental type.
const HEADER: usize = 16;

fn layout(size: usize) -> Layout {
    Layout::from_size_align(size.saturating_add(HEADER), HEADER)
        .unwrap_or_else(|_| handle_alloc_error(Layout::new::<u8>()))
}

/// `operator new(size_t)`: never returns null (the C++ form throws; here allocation failure
/// aborts, as Rust's does).
#[unsafe(no_mangle)]
pub extern "C" fn _Znwm(size: usize) -> *mut u8 {
    let layout = layout(size);
    // SAFETY: the layout's size is at least HEADER, never zero; the block starts with room
    // for the size (aligned to 16), and the caller gets the bytes after it.
    unsafe {
        let block = alloc(layout);
        if block.is_null() {
            handle_alloc_error(layout);
        }
        block.cast::<usize>().write(size);
        block.add(HEADER)
    }
}

/// `operator delete(void*)`: frees a block from [`_Znwm`]; null is allowed and does nothing.
///
/// # Safety
///
/// `pointer` is null or came from [`_Znwm`] and was not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn _ZdlPv(pointer: *mut u8) {
    if pointer.is_null() {
        return;
    }
    // SAFETY: by the contract, the block starts HEADER bytes before and holds its size.
    unsafe {
        let block = pointer.sub(HEADER);
        let size = block.cast::<usize>().read();
        dealloc(block, layout(size));
    }
}
