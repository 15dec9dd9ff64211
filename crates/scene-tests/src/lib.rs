//! # signorini-scene-tests
//!
//! No code: this crate holds the backend tests whose problems come from scenes (`tests/`): the
//! model (`signorini-core`) meshes and assembles a scene, one backend solves the QP.  They live
//! here, not in the backend crates, so that each backend crate depends on the QP contract
//! (`signorini-qp`) alone, in its tests too (`cargo metadata` shows no backend → model edge).
