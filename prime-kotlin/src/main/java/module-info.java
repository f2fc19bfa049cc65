/**
 * Prime from Kotlin: suspending calls of a chain's block, sources as flows and flows as sources
 * ({@code dev.prime.kotlin}), on the core and coroutines only (and SLF4J's API, which the core
 * brings).
 */
module dev.prime.kotlin {
  requires transitive dev.prime;
  requires transitive kotlin.stdlib;
  requires transitive kotlinx.coroutines.core;
  requires org.slf4j;

  exports dev.prime.kotlin;
}
