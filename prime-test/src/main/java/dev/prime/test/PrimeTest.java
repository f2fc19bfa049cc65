package dev.prime.test;

import dev.prime.test.internal.PrimeTestExtension;
import java.lang.annotation.Documented;
import java.lang.annotation.ElementType;
import java.lang.annotation.Retention;
import java.lang.annotation.RetentionPolicy;
import java.lang.annotation.Target;
import org.junit.jupiter.api.TestTemplate;
import org.junit.jupiter.api.extension.ExtendWith;

/**
 * Runs a test method once per {@linkplain Media media}, each time with a fresh {@link
 * dev.prime.PrimeCore} of that media.
 *
 * <pre>{@code
 * @PrimeTest
 * void doublesEveryReading(PrimeCore core) {
 *   EventBlock<Integer> sensor = new EventBlock<>();
 *   Reader<Integer> doubled = core.source("sensor", sensor).then(core.chain("twice", (Integer x) -> 2 * x)).reader();
 *   core.start();
 *   sensor.publish(1);
 *   sensor.publish(2);
 *   ReaderAssert.assertThat(doubled).emits(2, 4);
 * }
 * }</pre>
 *
 * <p>What it does:
 *
 * <ul>
 *   <li>The method runs once per media in {@link #media()}, in that order; each run is reported
 *       under the media's {@linkplain Media#displayName() name} ({@code Liberty}, {@code Radiant},
 *       {@code Optimus}, {@code Optimus, slow link}).
 *   <li>Parameters of type {@link dev.prime.PrimeCore} (of the test method and of its
 *       {@code @BeforeEach} and {@code @AfterEach} methods) receive the run's core, the same
 *       instance within one run; a parameter of type {@link Media} receives the run's media. A
 *       parameter typed as a media's own core class ({@code LibertyCore}, ...) is accepted on that
 *       media and refused with a clear message on the others.
 *   <li>The core is made (not started) on first use and closed after the run, after the
 *       {@code @AfterEach} methods, whether the test passed or failed. On Optimus its Redis keys
 *       are then deleted ({@code OptimusCore.deleteKeys()}), so a Redis the runs share keeps
 *       nothing of the runs that are over. The run fails if they cannot be deleted: with a
 *       {@code RedisUnavailableException} if Redis cannot be reached for 10 s, with an {@code
 *       IllegalStateException} if another core of the run's name is still open.
 *   <li>Every core has a name of its own ({@code test-liberty-1-k3f9}, ...: see {@link
 *       CoreSetup#configure}), so runs never see each other's sources or Redis keys.
 *   <li>Optimus runs share one Redis per test class: an embedded {@code redis-server} started
 *       for the first Optimus run of the class and stopped when the class is done, or the Redis
 *       named by the JUnit configuration parameter {@code prime.test.redis} (a {@code redis://}
 *       URL; then nothing is started).
 *   <li>{@link Media#OPTIMUS_SLOW_LINK}, run only when named ({@code @PrimeTest(media = {OPTIMUS,
 *       OPTIMUS_SLOW_LINK})}), is Optimus with that Redis behind a proxy that delays every byte
 *       each way by the JUnit configuration parameter {@code prime.test.slowLink.delay} ({@code
 *       2ms}, {@code 0.5ms}, ...; {@code 1ms} if unset): a slow network link, one per test class,
 *       closed with the class.
 *   <li>A media whose module is not on the test class path fails its run with a message naming
 *       the dependency to add.
 * </ul>
 */
@Documented
@Retention(RetentionPolicy.RUNTIME)
@Target({ElementType.METHOD, ElementType.ANNOTATION_TYPE})
@TestTemplate
@ExtendWith(PrimeTestExtension.class)
public @interface PrimeTest {

  /**
   * {@return the media to run on, in order; by default {@code LIBERTY}, {@code RADIANT} and {@code
   * OPTIMUS}} {@link Media#OPTIMUS_SLOW_LINK} runs only when named here. Each needs its module on
   * the test class path.
   */
  Media[] media() default {Media.LIBERTY, Media.RADIANT, Media.OPTIMUS};

  /**
   * {@return how each run's core is made} The default, {@code CoreSetup.class} itself, uses the
   * default settings and, on Optimus, the default codec.
   */
  Class<? extends CoreSetup> setup() default CoreSetup.class;
}
