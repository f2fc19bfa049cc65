/**
 * The logic of Prime's templates, written as plain {@link dev.prime.Block blocks} (logic layer).
 *
 * <p>{@link dev.prime.PrimeCore} builds its generic templates from these blocks; a media may
 * override a template to do better. They know nothing of chains or media and can be used, and
 * tested, on their own.
 */
package dev.prime.blocks;
