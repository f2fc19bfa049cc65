/**
 * The Optimus media: {@link dev.prime.optimus.OptimusCore} runs every chain as a coroutine service
 * over Redis lists. Only {@code dev.prime.optimus} is exported; its Kryo codec's internals ({@code
 * dev.prime.optimus.kryo}) are not. Jedis and Kryo are automatic modules (their jars name
 * themselves in their manifests), hence the suppressed warning.
 */
@SuppressWarnings("requires-automatic")
module dev.prime.optimus {
  requires transitive dev.prime;
  requires kotlin.stdlib;
  requires kotlinx.coroutines.core;
  requires org.slf4j;
  requires redis.clients.jedis;
  requires com.esotericsoftware.kryo;
  requires org.objenesis;

  exports dev.prime.optimus;
}
