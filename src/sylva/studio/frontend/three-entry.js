// Entry of static/vendor/three.js: the parts of three.js the Studio uses.
export * from "three";
export { GLTFLoader } from "three/examples/jsm/loaders/GLTFLoader.js";
