/**
 * The Radiant media: {@link dev.prime.radiant.RadiantCore} compiles every linked chain into one
 * generated class, so a service-oriented program runs as fast as direct calls.
 */
package dev.prime.radiant;
