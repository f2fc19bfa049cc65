/**
 * The Radiant media: {@link dev.prime.radiant.RadiantCore} compiles every linked chain into one
 * generated class. Only {@code dev.prime.radiant} is exported.
 */
module dev.prime.radiant {
  requires transitive dev.prime;
  requires net.bytebuddy;

  exports dev.prime.radiant;
}
