package dev.prime.optimus

/**
 * A publish found a service's input queue full ([OptimusCore.Builder.queueLimit]) and no room
 * came within [OptimusCore.Builder.publishTimeout]. Nothing of the publish was stored. The message
 * names the service, its limit and what to do. A [dev.prime.QueueFullException], the type every
 * media throws, so a program catches that one on any media.
 *
 * @property service the service whose queue is full, as the user named it
 * @property limit its queue limit
 */
public class QueueFullException internal constructor(
    public val service: String,
    public val limit: Int,
    message: String,
) : dev.prime.QueueFullException(service, limit.toLong(), message) {
    private companion object {
        private const val serialVersionUID: Long = 1L
    }
}
